#pragma once
// rdsim's small neural-network toolkit (Eigen, float, batches one column per sample):
// trainable tensors and gradient clipping, orthogonal init, networks (nn::Network: MLPs here, CNNs
// in cnn.hpp), Adam/RMSprop, parameter serialisation and action distributions.
#include "rdsim/nn/distributions.hpp"
#include "rdsim/nn/gemm.hpp"
#include "rdsim/nn/init.hpp"
#include "rdsim/nn/mlp.hpp"
#include "rdsim/nn/network.hpp"
#include "rdsim/nn/optimizer.hpp"
#include "rdsim/nn/param.hpp"
#include "rdsim/nn/serialize.hpp"

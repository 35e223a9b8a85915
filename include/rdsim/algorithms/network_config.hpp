#pragma once
#include <string>
#include <vector>

#include "rdsim/core/config_fields.hpp"

// The "network" object of a training config: the networks every algorithm builds. Each key is
// declared once, in describe() below (default = the member's initial value).
namespace rdsim {

// "network.cnn": the convolutional trunk used when the env observes pixels (UInt8 images, or the
// Float32 channels of EnvConfig::image_channels).
// "preset": "auto" = "small" below 84x84, "nature" at 84x84 and above;
//   "small"  = 16 8x8/4, 32 4x4/2, fc 256   (Mnih et al. 2013; 64x64 -> 6x6x32 features);
//   "nature" = 32 8x8/4, 64 4x4/2, 64 3x3/1, fc 512 (Mnih et al. 2015).
// Convs and fc use ReLU; with pixels the actor and critic always share the CNN (policy and value
// are linear heads on its features) and hidden_sizes/activation/shared are not used.
struct CnnConfig {
  std::string preset = "auto";
  std::vector<int> channels, kernels, strides;  // empty = the preset's
  std::vector<int> fc;                          // empty = the preset's
};

template <class V, class C>
  requires config::Describes<C, CnnConfig>
void describe(V& v, C& c) {
  v.choice("preset", c.preset, {"auto", "small", "nature"},
           "conv stack: small (16 8x8/4, 32 4x4/2, fc 256), nature (32 8x8/4, 64 4x4/2, 64 3x3/1, fc 512), "
           "auto = nature from 84x84 up");
  v.field("channels", c.channels, config::Range{1, 4096}, "output channels per conv layer; replaces the preset's convs");
  v.field("kernels", c.kernels, config::Range{1, 1024}, "square kernel size per conv layer (no padding)");
  v.field("strides", c.strides, config::Range{1, 1024}, "stride per conv layer");
  v.field("fc", c.fc, config::Range{1, 65536}, "dense layer sizes after the convs; replaces the preset's");
  v.check(c.kernels.size() == c.channels.size(), "kernels",
          "expected one kernel size per entry of channels (" + std::to_string(c.channels.size()) + "), got " +
              std::to_string(c.kernels.size()));
  v.check(c.strides.size() == c.channels.size(), "strides",
          "expected one stride per entry of channels (" + std::to_string(c.channels.size()) + "), got " +
              std::to_string(c.strides.size()));
}

struct NetworkConfig {
  std::vector<int> hidden_sizes = {64, 64};
  std::string activation = "tanh";
  bool shared = false;
  double log_std_init = 0.0;
  // Reaching tasks observe metres, where a few centimetres decide between a clear pass and a
  // collision; 10 (decimetres) brings such inputs near unit scale, so a tanh network draws sharp
  // boundaries without first growing large first-layer weights. One factor for all inputs keeps
  // distances isotropic (per-input running standardisation did worse on jaka_obstacle: README).
  double input_scale = 1.0;
  CnnConfig cnn;
};

template <class V, class C>
  requires config::Describes<C, NetworkConfig>
void describe(V& v, C& c) {
  v.field("hidden_sizes", c.hidden_sizes, config::Range{1, 65536}, "hidden layer widths of the MLPs");
  v.choice("activation", c.activation, {"tanh", "relu"}, "hidden-layer activation of the MLPs");
  v.field("shared", c.shared, "actor and critic share the hidden layers (one trunk, two heads)");
  v.field("log_std_init", c.log_std_init, config::Range{-20.0, 5.0},
          "initial log standard deviation of Gaussian (Box action) policies");
  v.field("input_scale", c.input_scale, config::Range{1e-6, 1e6},
          "vector observations are multiplied by this before the network (10: metres become decimetres)");
  v.object("cnn", c.cnn, "the convolutional trunk for pixel observations");
}

}  // namespace rdsim

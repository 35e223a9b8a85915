# ctest (tests/CMakeLists.txt): the policy example, linked with rdsim_policy alone, holds no
# simulation, rendering, env or training code: no shared library of Bullet, urdfdom, assimp,
# OSMesa, GL, ZeroMQ, ONNX or protobuf, and no symbol of rdsim's libraries above the policy one.
# cmake -DEXAMPLE=build/rdsim_policy_example -P tests/policy/links_alone.cmake
execute_process(COMMAND ldd ${EXAMPLE} OUTPUT_VARIABLE libraries RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "ldd ${EXAMPLE} failed (${status})")
endif()
foreach(library Bullet LinearMath urdfdom assimp OSMesa libGL libEGL zmq onnx protobuf)
  string(FIND "${libraries}" "${library}" at)
  if(NOT at EQUAL -1)
    message(FATAL_ERROR "${EXAMPLE} links ${library}:\n${libraries}")
  endif()
endforeach()
execute_process(COMMAND nm -C ${EXAMPLE} OUTPUT_VARIABLE symbols RESULT_VARIABLE status)
string(FIND "${symbols}" "rdsim::Policy::load" at)
if(NOT status EQUAL 0 OR at EQUAL -1)
  message(FATAL_ERROR "nm -C ${EXAMPLE} does not list rdsim::Policy::load")
endif()
foreach(symbol "rdsim::Algorithm" "rdsim::VecEnv" "rdsim::Trainer" "rdsim::TrainConfig" "rdsim::PhysicsWorld" "rdsim::Robot" "rdsim::make_env"
               "rdsim::Renderer" "btDiscreteDynamicsWorld" "btMultiBody" "OSMesa")
  string(FIND "${symbols}" "${symbol}" at)
  if(NOT at EQUAL -1)
    message(FATAL_ERROR "${EXAMPLE} holds ${symbol}")
  endif()
endforeach()
message(STATUS "${EXAMPLE}: no simulation, rendering, env or training code")

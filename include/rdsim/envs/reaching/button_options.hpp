#pragma once
#include "rdsim/core/config_fields.hpp"

// jaka_button's own option (besides the reaching tasks' ReachOptions), jaka_obstacle's too: which
// button stands on the table. One option group (core/env_options.hpp) in their defaults;
// envs/reaching/jaka_button.cpp implements it.
namespace rdsim {

enum class ButtonBody { Static, Paper };

struct ButtonOptions {
  ButtonBody button = ButtonBody::Static;
};

inline const config::Names<ButtonBody>& button_body_names() {
  static const config::Names<ButtonBody> names = {{"static", ButtonBody::Static}, {"paper", ButtonBody::Paper}};
  return names;
}

template <class V, class C>
  requires config::Describes<C, ButtonOptions>
void describe(V& v, C& c) {
  v.choice("button", c.button, button_body_names(),
           "static (rdsim's push button, 8 cm wide and 3 cm tall, fixed to the table; the target is the centre "
           "of its top) or paper (RobotDrlSim's: a free 5 kg box, 20 cm wide and 3.7 cm tall, standing on the "
           "table, which the arm can push away; the target is the centre of its bottom face, as the "
           "original's, and moves with it)");
}

}  // namespace rdsim

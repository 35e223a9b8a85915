#pragma once
#include <string>

#include "rdsim/core/config_fields.hpp"

// The "demonstrations" object of a training config: learning from a demonstration file
// (rdsim/demos/demo_file.hpp) before and during RL. What each algorithm does with it:
//   bc       behaviour cloning is the whole training: the actor is fitted to the demonstrated
//            actions (cross-entropy for Discrete, Gaussian log-likelihood for Box);
//   ppo, a2c the same fit pre-trains the actor, and (fit_critic) the critic is fitted to the
//            demonstrations' discounted returns, before the first rollout; with bc_weight > 0 the
//            cloning loss stays in RL's loss with a weight that decays every update (DAPG's
//            schedule, Rajeswaran et al. 2018): each minibatch adds
//            bc_weight x bc_weight_decay^(update - 1) x mean -log pi(a_demo | s_demo) over as many
//            demonstrated steps, which keeps the first updates from undoing the cloned policy;
//   dqn      the demonstrations seed a replay buffer of their own that is never overwritten; every
//            minibatch draws demo_fraction of its transitions from it; bc_epochs passes over it with
//            the TD loss (plus, with large_margin, DQfD's large-margin loss on demonstrated actions,
//            Hester et al. 2018) pre-train the Q-network, and that loss keeps applying to the
//            demonstrated transitions during training;
//   sac, td3, ddpg  the same kind of buffer and demo_fraction (with hindsight goals under "her"),
//            bc_epochs passes of the algorithm's own gradient steps on the demonstrations alone,
//            and with bc_weight > 0 a Q-filtered cloning term in the actor's loss (Nair et al. 2018):
//            bc_weight x mean |pi(s) - a_demo|^2 over the demonstrated transitions whose action the
//            critic values above the policy's (demonstration_replay.hpp, off_policy.hpp); on goal
//            envs with Cartesian actions, `shift` moves each drawn demonstrated transition on the
//            table (a data augmentation: the same actions from other positions), and `scatter`
//            moves the objects a demonstrated step does not depend on to other places.
// Every algorithm that steps envs can also start a share of its training episodes from states of
// the demonstrations (start_fraction; training/demonstration_starts.hpp), or of another file of the
// same task (start_file), and in manipulation tasks draw a new layout around those states
// (start_redraw).
// The actor fits hold out whole episodes (validation_fraction) and stop early: after `patience`
// epochs without a better validation loss they restore the best epoch's weights.
namespace rdsim {

struct DemonstrationsConfig {
  std::string file;
  int bc_epochs = 100;
  int batch_size = 256;
  double learning_rate = 1e-3;
  double validation_fraction = 0.2;
  int patience = 10;
  bool fit_critic = true;
  double bc_weight = 0.0;
  double bc_weight_decay = 0.95;
  double demo_fraction = 0.25;
  double start_fraction = 0.0;
  std::string start_file;  // empty: `file`
  double start_redraw = 0.0;  // the share of those starts with a new layout
  double shift = 0.0;      // m: sac/td3/ddpg on goal envs, the planar shift of demonstrated transitions
  double scatter = 0.0;       // sac/td3/ddpg on goal envs with objects: the share of them scattered
  bool scatter_goal = false;  // and the goal too, before the first object moves
  bool large_margin = false;
  double margin = 0.8;
  double margin_weight = 1.0;
};

template <class V, class C>
  requires config::Describes<C, DemonstrationsConfig>
void describe(V& v, C& c) {
  v.field("file", c.file, "demonstration file (`rdsim demos record`, `rdsim teleop --record`)");
  v.check(!c.file.empty(), "file", "expected the path of a demonstration file");
  v.field("bc_epochs", c.bc_epochs, config::Range{0, 100'000},
          "passes over the demonstrations before RL (bc: the whole training); 0 = none");
  v.field("batch_size", c.batch_size, config::Range{1, 1'000'000}, "transitions per gradient step of the pre-training");
  v.field("learning_rate", c.learning_rate, config::Range{0.0, 1.0}, "Adam step size of the pre-training");
  v.field("validation_fraction", c.validation_fraction, config::Range{0.0, 0.9},
          "share of the episodes held out to stop the actor fit early (at least one when > 0 and there are two)");
  v.field("patience", c.patience, config::Range{1, 100'000},
          "epochs without a better validation loss before the fit stops and restores the best weights");
  v.field("fit_critic", c.fit_critic, "ppo/a2c: also fit the critic to the demonstrations' discounted returns");
  v.field("bc_weight", c.bc_weight, config::Range{0.0, 1e6},
          "ppo/a2c: weight of the cloning loss kept in RL's loss (0 = pre-training only); sac/td3/ddpg: weight of "
          "the Q-filtered cloning loss in the actor's");
  v.field("bc_weight_decay", c.bc_weight_decay, config::Range{0.0, 1.0}, "ppo/a2c: factor on bc_weight per update");
  v.field("demo_fraction", c.demo_fraction, config::Range{0.0, 1.0},
          "dqn, sac, td3, ddpg: share of every minibatch drawn from the demonstrations");
  v.field("start_fraction", c.start_fraction, config::Range{0.0, 1.0},
          "share of the training episodes that start from a demonstration's state: a demonstrated episode and a "
          "step along it drawn uniformly, replayed from its seed (Nair et al. 2018); every algorithm but bc");
  v.field("start_file", c.start_file,
          "demonstration file whose states start those episodes, when not `file` (e.g. episodes that show a "
          "recovery the cloned ones should not); empty = `file`");
  v.check(c.start_file.empty() || c.start_fraction > 0.0, "start_file", "has no effect without start_fraction above 0");
  v.field("start_redraw", c.start_redraw, config::Range{0.0, 1.0},
          "share of those starts in which what the demonstrator has not moved yet is drawn again: the arm and what "
          "it has done stay (a cube in the gripper, a cube on its goal), the cubes still where the reset put them "
          "and the goal (unless a cube is on it) get new places, so that a few demonstrations start episodes in "
          "new layouts; manipulation tasks; 0 = none");
  v.check(c.start_redraw == 0.0 || c.start_fraction > 0.0, "start_redraw", "has no effect without start_fraction above 0");
  v.field("shift", c.shift, config::Range{0.0, 1.0},
          "sac/td3/ddpg on goal envs with Cartesian actions: each demonstrated transition drawn into a minibatch is "
          "moved on the table by an offset drawn uniformly in [-shift, shift] m on x and on y, every world position "
          "of its observations (effector, objects, goals) together, so that 50 demonstrations cover other layouts "
          "(demonstration_replay.hpp); 0 = none");
  v.field("scatter", c.scatter, config::Range{0.0, 1.0},
          "sac/td3/ddpg on goal envs with objects: the share of the demonstrated transitions drawn into a minibatch "
          "whose idle objects (not moved yet and not the next one the demonstrator moves: stack's second cube while "
          "the first is fetched and placed) get new places on the table, where the demonstrations' objects started "
          "and clear of the effector and the rest (demonstration_scatter.hpp); 0 = none");
  v.field("scatter_goal", c.scatter_goal,
          "with scatter: the goal too gets a new place while no object has moved yet; right for demonstrators "
          "whose way to the first object does not depend on the goal (the scripted expert's pick_and_place and "
          "stack, not push)");
  v.check(!c.scatter_goal || c.scatter > 0.0, "scatter_goal", "has no effect without scatter above 0");
  v.field("large_margin", c.large_margin, "dqn: DQfD's large-margin loss on demonstrated actions");
  v.field("margin", c.margin, config::Range{0.0, 1e6}, "dqn: the margin by which a demonstrated action's Q must lead");
  v.field("margin_weight", c.margin_weight, config::Range{0.0, 1e6}, "dqn: weight of the large-margin loss");
}

}  // namespace rdsim

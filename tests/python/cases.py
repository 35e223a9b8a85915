"""Every env, observation mode and action kind the checkers run on (small images: fast)."""
import rdsim

# SB3's image check asks for at least 36 x 36 pixels; that size keeps the pixel cases fast.
PIXELS = {"observation": "raw_pixels", "image_width": 36, "image_height": 36}


def action_kinds(env_id):
    """The is_discrete values an env accepts (cartpole: Discrete only; pendulum: Box only)."""
    kinds = []
    for discrete in (True, False):
        try:
            rdsim.make(env_id, is_discrete=discrete).close()
            kinds.append(discrete)
        except rdsim.Error:
            pass
    return kinds


def has_joint_control(env_id):
    """Whether the env takes "control": "joints" (the manipulation tasks)."""
    probe = rdsim.make(env_id)
    try:
        return "control" in probe.unwrapped.config
    finally:
        probe.close()


def env_cases():
    """(id, options) for every env x observation mode x action kind it has."""
    cases = []
    for env in rdsim.envs():
        for discrete in action_kinds(env["id"]):
            cases.append((env["id"], {"is_discrete": discrete}))
            if env["supports_pixels"]:
                cases.append((env["id"], {"is_discrete": discrete, **PIXELS}))
            if has_joint_control(env["id"]) and not discrete:  # joint moves are Box actions
                cases.append((env["id"], {"is_discrete": discrete, "control": "joints"}))
    return cases


def case_name(case):
    env_id, options = case
    return f"{env_id.split('/')[1]}-{'pixels' if 'observation' in options else 'state'}-" + (
        "joints-" if options.get("control") == "joints" else "") + (
        "discrete" if options["is_discrete"] else "box")


def advice_only(env_id, caught):
    """The warnings of `caught` that are not the checkers' advice to normalise a Box action space to
    [-1, 1]. Pendulum-v1's torque space is Box(-2, 2), Gymnasium's own Pendulum-v1's, kept for the same
    dynamics: that advice is the one warning allowed, and only for it."""
    advice = "symmetric and normalized"
    return [w for w in caught if not (env_id == "rdsim/Pendulum-v1" and advice in str(w.message))]

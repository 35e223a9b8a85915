"""Every env, observation mode and action kind the checkers run on (small images: fast)."""
import rdsim

# SB3's image check asks for at least 36 x 36 pixels; that size keeps the pixel cases fast.
PIXELS = {"observation": "raw_pixels", "image_width": 36, "image_height": 36}


def env_cases():
    """(id, options) for every env x observation mode x action kind."""
    cases = []
    for env in rdsim.envs():
        for discrete in (True, False):
            cases.append((env["id"], {"is_discrete": discrete}))
            if env["supports_pixels"]:
                cases.append((env["id"], {"is_discrete": discrete, **PIXELS}))
    return cases


def case_name(case):
    env_id, options = case
    return f"{env_id.split('/')[1]}-{'pixels' if 'observation' in options else 'state'}-" + (
        "discrete" if options["is_discrete"] else "box")

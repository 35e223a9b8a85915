#!/usr/bin/env python3
"""Writes the malformed-input corpus of tests/malformed/ (run by tests/app/test_malformed_inputs.cpp).

Every case is an input a user could give rdsim that must end with ONE line
`rdsim: error: ...` naming the file/key/option, exit status 1, no crash, no hang, bounded memory.
The manifest cases.tsv has one case per line, tab-separated:
    kind    input    target    expected
kind:     config (train --config INPUT), urdf (INPUT replaces the asset TARGET, train on the
          env using it), mesh (INPUT is a mesh file copied to the asset path TARGET, e.g.
          jaka/mesh.stl, and urdfs/jaka-mesh-EXT.urdf, the Jaka URDF whose base link shows
          mesh.EXT, replaces jaka/jaka_zu7.urdf; train on jaka_button), cli (TARGET is the
          argument list, with {root} the repository, {tmp} a scratch folder, {big} a 16 MiB + 2
          byte config; INPUT is -).
expected: a fragment the message must contain (besides the file name for config/urdf cases).
Model and checkpoint cases are made by the test itself from a model it trains (their bytes
depend on the current format), see the test file.

Run from the repository root: /usr/bin/python3 tools/gen_malformed_corpus.py
"""
import json
import os
import shutil

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
OUT = os.path.join(ROOT, "tests", "malformed")

BASE = {
    "algorithm": "ppo",
    "env": {"name": "cartpole"},
    "seed": 1,
    "total_timesteps": 2048,
    "num_envs": 2,
    "network": {"hidden_sizes": [16, 16]},
    "ppo": {"n_steps": 64, "batch_size": 64, "n_epochs": 1},
}
ROBOT = {
    "algorithm": "ppo",
    "env": {"name": "jaka_button"},
    "seed": 1,
    "total_timesteps": 2048,
    "num_envs": 1,
    "network": {"hidden_sizes": [16]},
    "ppo": {"n_steps": 64, "batch_size": 64, "n_epochs": 1},
}
DQN = {
    "algorithm": "dqn",
    "env": {"name": "cartpole"},
    "seed": 1,
    "total_timesteps": 2048,
    "network": {"hidden_sizes": [16]},
    "dqn": {"buffer_size": 1000, "learning_starts": 100, "batch_size": 32},
}
A2C = {
    "algorithm": "a2c",
    "env": {"name": "cartpole"},
    "seed": 1,
    "total_timesteps": 2048,
    "network": {"hidden_sizes": [16]},
    "a2c": {"n_steps": 8},
}

cases = []  # (kind, input, target, expected)


def deep_set(obj, path, value):
    obj = json.loads(json.dumps(obj))
    node = obj
    keys = path.split(".")
    for k in keys[:-1]:
        node = node.setdefault(k, {})
    if value is DELETE:
        node.pop(keys[-1], None)
    else:
        node[keys[-1]] = value
    return obj


DELETE = object()


def config_case(name, text, expected):
    path = os.path.join("configs", name + ".json")
    with open(os.path.join(OUT, path), "w", encoding="utf-8", newline="") as f:
        f.write(text)
    cases.append(("config", path, "-", expected))


def mutate(name, base, path, value, expected):
    config_case(name, json.dumps(deep_set(base, path, value), indent=1), expected)


def raw(name, text, expected):
    config_case(name, text, expected)


def gen_configs():
    # --- top-level run settings: every key, wrong types and out-of-range values
    for value, tag in [(-1, "negative"), (1.5, "fraction"), ("1", "string"), (True, "bool"), (None, "null"),
                       ([], "list"), ({}, "object"), (18446744073709551616, "2pow64")]:
        mutate("seed-" + tag, BASE, "seed", value, "seed: expected an integer in [0, 2^64 - 1]")
    for value, tag in [(0, "zero"), (-5, "negative"), (1e13, "1e13"), (1.5, "fraction"), ("100", "string"),
                       (None, "null"), (10 ** 19, "huge")]:
        mutate("total_timesteps-" + tag, BASE, "total_timesteps", value, "total_timesteps: expected an integer in [1, 1e12]")
    for value, tag in [(0, "zero"), (5000, "5000"), (-1, "negative"), (2.5, "fraction"), ("4", "string")]:
        mutate("num_envs-" + tag, BASE, "num_envs", value, "num_envs: expected an integer in [1, 4096]")
    for value, tag in [(5, "number"), (["runs"], "list"), ("a\u0000b", "nul"), ("a\nb", "newline"), ("x" * 5000, "long")]:
        mutate("log_dir-" + tag, BASE, "log_dir", value, "log_dir: expected a string")
    for value, tag in [(-1, "negative"), (1e13, "huge"), ("often", "string"), (0.5, "fraction")]:
        mutate("checkpoint_interval-" + tag, BASE, "checkpoint_interval", value, "checkpoint_interval: expected an integer")
    for value, tag in [(-1, "negative"), (1e7, "huge"), ("minute", "string"), (None, "null")]:
        mutate("checkpoint_seconds-" + tag, BASE, "checkpoint_seconds", value, "checkpoint_seconds: expected a number in [0, 1e6]")
    for value, tag in [(0, "zero"), (2000000, "huge"), ("20", "string")]:
        mutate("stats_window-" + tag, BASE, "stats_window", value, "stats_window: expected an integer")
    for value, tag in [("ppo2", "unknown"), (5, "number"), (None, "null"), ("", "empty"), ("PPO", "case")]:
        mutate("algorithm-" + tag, BASE, "algorithm", value, "algorithm: expected ")
    mutate("unknown-top-key", BASE, "learning_rate", 0.001, "learning_rate: unknown key")
    mutate("unknown-typo", BASE, "total_timestep", 100, "total_timestep: unknown key")
    mutate("other-algorithm-object", BASE, "dqn", {"batch_size": 32}, "dqn: has no effect")
    mutate("other-algorithm-object-a2c", BASE, "a2c", {}, "a2c: has no effect")

    # --- env
    mutate("env-missing", BASE, "env", DELETE, "env: missing")
    for value, tag in [([], "list"), ("cartpole", "string"), (None, "null"), (5, "number")]:
        mutate("env-" + tag, BASE, "env", value, "env: expected a JSON object")
    mutate("env-name-unknown", BASE, "env.name", "nope", "env.name: unknown environment")
    mutate("env-name-empty", BASE, "env.name", "", "env.name: expected an environment name")
    mutate("env-name-number", BASE, "env.name", 5, "env.name: expected a string")
    mutate("env-name-missing", BASE, "env", {"max_steps": 10}, "env.name")
    mutate("env-unknown-key", BASE, "env.colour", "red", "env.colour: unknown key")
    for key, value in [("urdf_root", "assets"), ("random_target", True), ("action_step", 0.01), ("image_width", 64),
                       ("multi_view", False), ("renderer", "egl"), ("render_mode", "rgb_array")]:
        mutate("cartpole-" + key, BASE, "env." + key, value, "env." + key + ": has no effect on cartpole")
    mutate("cartpole-pixels", BASE, "env.observation", "raw_pixels", "env.observation: cartpole has no camera")
    mutate("cartpole-continuous", BASE, "env.is_discrete", False, "env.is_discrete")
    for value, tag in [(0, "zero"), (-1, "negative"), (1e9, "huge"), ("500", "string")]:
        mutate("env-max_steps-" + tag, BASE, "env.max_steps", value, "env.max_steps: expected an integer in [1, 1e8]")
    mutate("env-observation-unknown", BASE, "env.observation", "rgb", "env.observation: expected one of")
    mutate("env-is_discrete-string", BASE, "env.is_discrete", "yes", "env.is_discrete: expected true or false")
    # robot env options
    for key, value, expected in [
        ("multi_view", True, "env.multi_view: has no effect without"),
        ("image_width", 128, "env.image_width: has no effect without"),
        ("image_height", 32, "env.image_height: has no effect without"),
        ("render_width", 100, "env.render_width: has no effect without"),
        ("render_height", 100, "env.render_height: has no effect without"),
        ("renderer", "egl", "env.renderer: has no effect when nothing is drawn"),
        ("max_distance", 0, "env.max_distance: expected a number"),
        ("max_distance", 1e9, "env.max_distance: expected a number"),
        ("action_step", 5, "env.action_step: expected a number"),
        ("action_step", -0.01, "env.action_step: expected a number"),
        ("success_threshold", -1, "env.success_threshold: expected a number"),
        ("action_repeat", 0, "env.action_repeat: expected an integer"),
        ("action_repeat", 10000, "env.action_repeat: expected an integer"),
        ("max_steps", 0, "env.max_steps: expected an integer"),
        ("render_mode", "human", "env.render_mode: expected one of"),
        ("renderer", "vulkan", "env.renderer: expected one of"),
        ("random_target", "yes", "env.random_target: expected true or false"),
        ("urdf_root", 3, "env.urdf_root: expected a string"),
        ("urdf_root", "/nonexistent/rdsim/assets", "/nonexistent/rdsim/assets"),
    ]:
        mutate("jaka-%s-%s" % (key, str(value).replace("/", "_")[:12]), ROBOT, "env." + key, value, expected)
    pixels = deep_set(ROBOT, "env.observation", "raw_pixels")
    pixels = deep_set(pixels, "network", {})
    for key, value, expected in [("image_width", 0, "env.image_width: expected an integer in [8, 4096]"),
                                 ("image_width", 5000, "env.image_width: expected an integer in [8, 4096]"),
                                 ("image_height", 4, "env.image_height: expected an integer in [8, 4096]"),
                                 ("image_width", 8.5, "env.image_width: expected an integer")]:
        mutate("pixels-%s-%s" % (key, value), pixels, "env." + key, value, expected)
    big = deep_set(deep_set(deep_set(pixels, "env.image_width", 4096), "env.image_height", 4096), "num_envs", 64)
    mutate("pixels-4096-x64-memory", big, "env.multi_view", True, "this run would need about")
    mutate("pixels-1024-memory", deep_set(deep_set(pixels, "env.image_width", 1024), "env.image_height", 1024),
           "num_envs", 256, "this run would need about")
    mutate("pixels-hidden_sizes", pixels, "network.hidden_sizes", [32], "network.hidden_sizes: has no effect with raw-pixel")
    mutate("pixels-input_scale", pixels, "network.input_scale", 10, "network.input_scale: only for vector observations")
    mutate("pixels-cnn-too-deep", pixels, "network.cnn", {"channels": [8, 8, 8, 8], "kernels": [8, 8, 8, 8], "strides": [4, 4, 4, 4]},
           "network.cnn")
    mutate("inmoov-num_envs-memory", deep_set(ROBOT, "env.name", "inmoov_tomato"), "num_envs", 4096, "this run would need about")

    # --- network
    for value, tag, expected in [([0], "zero", "network.hidden_sizes: expected a list"),
                                 ([-1], "negative", "network.hidden_sizes: expected a list"),
                                 ([65537], "too-wide", "network.hidden_sizes: expected a list"),
                                 ([64.5], "fraction", "network.hidden_sizes: expected a list"),
                                 ("64", "string", "network.hidden_sizes: expected a list"),
                                 ([64] * 300, "300-layers", "network.hidden_sizes: expected a list of at most 256"),
                                 ([65536, 65536], "65536x2-memory", "this run would need about"),
                                 ([4096] * 200, "deep-wide-memory", "this run would need about"),
                                 ([[64]], "nested", "network.hidden_sizes: expected a list"),
                                 (None, "null", "network.hidden_sizes: expected a list")]:
        mutate("network-hidden_sizes-" + tag, BASE, "network.hidden_sizes", value, expected)
    for key, value, expected in [("activation", "sigmoid", "network.activation: expected one of"),
                                 ("activation", 3, "network.activation: expected a string"),
                                 ("shared", "yes", "network.shared: expected true or false"),
                                 ("log_std_init", 10, "network.log_std_init: expected a number in [-20, 5]"),
                                 ("log_std_init", -1, "network.log_std_init: has no effect with discrete actions"),
                                 ("input_scale", 0, "network.input_scale: expected a number"),
                                 ("input_scale", 1e7, "network.input_scale: expected a number"),
                                 ("cnn", {"preset": "small"}, "network.cnn: has no effect with ground-truth"),
                                 ("cnn", {"preset": "big"}, "network.cnn.preset: expected one of"),
                                 ("cnn", {"channels": [8]}, "network.cnn.kernels: expected one kernel size"),
                                 ("cnn", 5, "network.cnn: expected a JSON object"),
                                 ("dropout", 0.5, "network.dropout: unknown key")]:
        mutate("network-%s-%d" % (key, len(cases)), BASE, "network." + key, value, expected)
    mutate("network-not-object", BASE, "network", [16], "network: expected a JSON object")

    # --- ppo
    for key, value, expected in [("n_steps", 0, "ppo.n_steps: expected an integer in [1, 1e6]"),
                                 ("n_steps", 2000000, "ppo.n_steps: expected an integer in [1, 1e6]"),
                                 ("batch_size", 0, "ppo.batch_size: expected an integer"),
                                 ("batch_size", 4096, "ppo.batch_size: expected at most the rollout size"),
                                 ("n_epochs", 0, "ppo.n_epochs: expected an integer"),
                                 ("learning_rate", -1, "ppo.learning_rate: expected a number in [0, 1]"),
                                 ("learning_rate", 2, "ppo.learning_rate: expected a number in [0, 1]"),
                                 ("learning_rate", "fast", "ppo.learning_rate: expected a number"),
                                 ("gamma", 1.5, "ppo.gamma: expected a number in [0, 1]"),
                                 ("gae_lambda", -0.1, "ppo.gae_lambda: expected a number"),
                                 ("clip_range", 11, "ppo.clip_range: expected a number in [0, 10]"),
                                 ("ent_coef", -1, "ppo.ent_coef: expected a number"),
                                 ("vf_coef", 101, "ppo.vf_coef: expected a number"),
                                 ("max_grad_norm", 0, "ppo.max_grad_norm: expected a number in [1e-9, 1e9]"),
                                 ("target_kl", -1, "ppo.target_kl: expected a number"),
                                 ("anneal_lr", "yes", "ppo.anneal_lr: expected true or false"),
                                 ("n_stepz", 8, "ppo.n_stepz: unknown key"),
                                 ("adam_eps", 2, "ppo.adam_eps: expected a number"),
                                 ("clip_range_vf", -1, "ppo.clip_range_vf: expected a number")]:
        mutate("ppo-%s-%s" % (key, str(value)), BASE, "ppo." + key, value, expected)
    mutate("ppo-not-object", BASE, "ppo", 5, "ppo: expected a JSON object")
    # --- a2c
    for key, value, expected in [("optimizer", "sgd", "a2c.optimizer: expected one of"),
                                 ("rms_alpha", 2, "a2c.rms_alpha: expected a number in [0, 1]"),
                                 ("n_steps", 0, "a2c.n_steps: expected an integer"),
                                 ("gamma", -1, "a2c.gamma: expected a number")]:
        mutate("a2c-%s-%s" % (key, value), A2C, "a2c." + key, value, expected)
    mutate("a2c-adam-rms_alpha", deep_set(A2C, "a2c.optimizer", "adam"), "a2c.rms_alpha", 0.5,
           "a2c.rms_alpha: has no effect with optimizer \"adam\"")
    mutate("a2c-adam-rms_tf_style", deep_set(A2C, "a2c.optimizer", "adam"), "a2c.rms_tf_style", True,
           "a2c.rms_tf_style: has no effect with optimizer \"adam\"")
    # --- dqn
    for key, value, expected in [("batch_size", 5000, "dqn.batch_size: expected at most buffer_size"),
                                 ("buffer_size", 0, "dqn.buffer_size: expected an integer in [1, 1e8]"),
                                 ("exploration_final_eps", 1.5, "dqn.exploration_final_eps: expected a number in [0, 1]"),
                                 ("exploration_initial_eps", 0.01, "dqn.exploration_final_eps: expected at most exploration_initial_eps"),
                                 ("learning_starts", 5000, "dqn.learning_starts: expected fewer than total_timesteps"),
                                 ("tau", 2, "dqn.tau: expected a number in [0, 1]"),
                                 ("train_freq", 0, "dqn.train_freq: expected an integer"),
                                 ("gradient_steps", -1, "dqn.gradient_steps: expected an integer"),
                                 ("target_update_interval", 0, "dqn.target_update_interval: expected an integer"),
                                 ("buffer_size", 100000000, "this run would need about")]:
        mutate("dqn-%s-%s" % (key, value), DQN, "dqn." + key, value, expected)
    robot_dqn = deep_set(deep_set(DQN, "env", {"name": "jaka_button", "is_discrete": False}), "num_envs", 1)
    config_case("dqn-continuous-actions", json.dumps(robot_dqn), "needs a discrete action space")
    pixel_dqn = deep_set(deep_set(DQN, "env", {"name": "jaka_button", "observation": "raw_pixels", "image_width": 512,
                                               "image_height": 512}), "network", {})
    mutate("dqn-eps-order", deep_set(DQN, "dqn.exploration_initial_eps", 0.5), "dqn.exploration_final_eps", 0.8,
           "dqn.exploration_final_eps: expected at most exploration_initial_eps")
    mutate("dqn-pixels-replay-memory", pixel_dqn, "dqn.buffer_size", 1000000, "this run would need about")

    # --- JSON itself
    raw("json-empty", "", "not valid JSON")
    raw("json-whitespace", "   \n\t ", "not valid JSON")
    raw("json-open-brace", "{", "not valid JSON")
    raw("json-array", "[]", "top level: expected a JSON object")
    raw("json-null", "null", "top level: expected a JSON object")
    raw("json-number", "5", "top level: expected a JSON object")
    raw("json-string", "\"cartpole\"", "top level: expected a JSON object")
    raw("json-trailing-comma", '{"env": {"name": "cartpole"},}', "not valid JSON")
    raw("json-comment", '// config\n{"env": {"name": "cartpole"}}', "not valid JSON")
    raw("json-block-comment", '{"env": {"name": "cartpole"} /* x */}', "not valid JSON")
    raw("json-nan", '{"env": {"name": "cartpole"}, "seed": NaN}', "not valid JSON")
    raw("json-infinity", '{"env": {"name": "cartpole"}, "ppo": {"gamma": Infinity}}', "not valid JSON")
    raw("json-1e400", '{"env": {"name": "cartpole"}, "ppo": {"learning_rate": 1e400}}', "1e400")
    raw("json-minus-1e400", '{"env": {"name": "cartpole"}, "ppo": {"learning_rate": -1e400}}', "1e400")
    raw("json-1e400-integer-key", '{"env": {"name": "cartpole"}, "total_timesteps": 1e400}', "1e400")
    raw("json-leading-zero", '{"env": {"name": "cartpole"}, "seed": 01}', "not valid JSON")
    raw("json-plus-sign", '{"env": {"name": "cartpole"}, "seed": +1}', "not valid JSON")
    raw("json-hex", '{"env": {"name": "cartpole"}, "seed": 0x10}', "not valid JSON")
    raw("json-single-quotes", "{'env': {'name': 'cartpole'}}", "not valid JSON")
    raw("json-unquoted-key", '{env: {"name": "cartpole"}}', "not valid JSON")
    raw("json-two-values", '{"env": {"name": "cartpole"}} {}', "not valid JSON")
    raw("json-unterminated-string", '{"env": {"name": "cartpole}}', "not valid JSON")
    raw("json-control-char-in-string", '{"env": {"name": "cart\x01pole"}}', "not valid JSON")
    raw("json-bad-escape", '{"env": {"name": "cart\\qpole"}}', "not valid JSON")
    raw("json-bad-unicode-escape", '{"env": {"name": "\\ud800"}}', "not valid JSON")
    raw("json-duplicate-top-key", '{"env": {"name": "cartpole"}, "seed": 1, "seed": 2}', "seed: duplicate key")
    raw("json-duplicate-nested-key", '{"env": {"name": "cartpole", "name": "jaka_button"}}', "env.name: duplicate key")
    raw("json-duplicate-ppo-key", '{"env": {"name": "cartpole"}, "ppo": {"n_steps": 64, "n_steps": 128}}',
        "ppo.n_steps: duplicate key")
    raw("json-duplicate-env", '{"env": {"name": "cartpole"}, "env": {"name": "jaka_button"}}', "env: duplicate key")
    raw("json-nested-100", '{"env": {"name": "cartpole"}, "x": ' + "[" * 100 + "]" * 100 + "}", "nested more than 64")
    raw("json-nested-60000", '{"env": {"name": "cartpole"}, "x": ' + "[" * 60000 + "]" * 60000 + "}", "nested more than 64")
    raw("json-nested-objects", '{"env": {"name": "cartpole"}, "x": ' + '{"a":' * 2000 + "1" + "}" * 2000 + "}",
        "nested more than 64")
    raw("json-nested-unclosed", "[" * 70000, "nested more than 64")
    raw("json-deep-value-in-known-key", '{"env": {"name": "cartpole"}, "seed": ' + "[" * 50 + "]" * 50 + "}",
        "seed: expected an integer")
    with open(os.path.join(OUT, "configs", "json-invalid-utf8.json"), "wb") as f:
        f.write(b'{"env": {"name": "cart\xff\xfepole"}}')
    cases.append(("config", "configs/json-invalid-utf8.json", "-", "not valid JSON"))
    with open(os.path.join(OUT, "configs", "json-nul-byte.json"), "wb") as f:
        f.write(b'{"env": {"name": "cartpole"}\x00, "seed": 1}')
    cases.append(("config", "configs/json-nul-byte.json", "-", "not valid JSON"))
    with open(os.path.join(OUT, "configs", "json-binary.json"), "wb") as f:
        f.write(bytes(range(256)) * 4)
    cases.append(("config", "configs/json-binary.json", "-", "not valid JSON"))
    raw("json-long-unknown-key", '{"env": {"name": "cartpole"}, "' + "k" * 20000 + '": 1}', "unknown key")
    raw("json-long-string-value", '{"env": {"name": "' + "c" * 20000 + '"}}', "env.name")
    raw("json-huge-list", '{"env": {"name": "cartpole"}, "network": {"hidden_sizes": [' + ",".join(["8"] * 2000) + "]}}",
        "network.hidden_sizes: expected a list of at most 256")
    raw("json-newline-in-key", '{"env": {"name": "cartpole"}, "se\\ned": 1}', "unknown key")


def gen_cli():
    c = "{root}/configs/cartpole_ppo.json"  # a valid config
    for args, expected in [
        ("trian", 'unknown command "trian" (did you mean "train"?)'),
        ("replya x.bin", 'did you mean "replay"'),
        ("bench", 'did you mean "bench-fps"'),
        ("xyzzy-frobnicate", 'unknown command "xyzzy-frobnicate"'),
        ("", "A subcommand is required"),
        ("--frobnicate", 'unknown option "--frobnicate"'),
        ("--frobnicate train", 'unknown option "--frobnicate"'),
        ("train", "give --config FILE or --resume DIR"),
        ("train --config", "--config"),
        ("train --config {c} --seed -1 --log-dir {tmp}/r", "--seed: seed: expected an integer in [0, 2^64 - 1], got -1"),
        ("train --config {c} --seed 1.5 --log-dir {tmp}/r", "--seed: seed: expected an integer"),
        ("train --config {c} --seed abc --log-dir {tmp}/r", "--seed: seed: expected an integer"),
        ("train --config {c} --seed 18446744073709551616 --log-dir {tmp}/r", "--seed: seed: expected an integer"),
        ("train --config {c} --timesteps 1e18 --log-dir {tmp}/r", "--timesteps: total_timesteps: expected an integer in [1, 1e12], got 1e+18"),
        ("train --config {c} --timesteps 0 --log-dir {tmp}/r", "--timesteps: total_timesteps: expected an integer in [1, 1e12]"),
        ("train --config {c} --timesteps -5 --log-dir {tmp}/r", "--timesteps: total_timesteps"),
        ("train --config {c} --timesteps 1e400 --log-dir {tmp}/r", "--timesteps: total_timesteps"),
        ("train --config {c} --timesteps many --log-dir {tmp}/r", "--timesteps: total_timesteps"),
        ("train --config {c} --log-dir ''", "--log-dir: expected a value, got an empty string"),
        ("train --config {c} --max-memory 0 --log-dir {tmp}/r", "--max-memory"),
        ("train --config {c} --max-memory 0.000001 --log-dir {tmp}/r", "--max-memory"),
        ("train --config {c} --max-memory lots --log-dir {tmp}/r", "--max-memory"),
        ("train --config {root}/configs/jaka_button_pixels.json --max-memory 0.001 --log-dir {tmp}/r", "more than the limit of 1 MB (--max-memory 0.001)"),
        ("train --config {c} --resume {tmp}", "excludes"),
        ("train --resume {tmp}/none", "no such run folder to resume"),
        ("train --resume {tmp}", "checkpoint.bin: cannot open"),
        ("train --resume {tmp}/none --seed 3", "--seed cannot change a resumed run"),
        ("train --resume {tmp}/none --log-dir {tmp}/x", "--log-dir cannot be combined with --resume"),
        ("train --resume {tmp}/none --overwrite", "--overwrite cannot be combined with --resume"),
        ("train --config {tmp}/absent.json", "absent.json: cannot open"),
        ("train --config {tmp}", "is a folder"),
        ("train --config /dev/zero", "/dev/zero: is not a regular file (it is a character device)"),
        ("train --config {big}", "more than the 16777216 bytes"),
        ("train --config {c} --unknown-flag", "unknown-flag"),
        ("train --config {c} extra-arg", "extra-arg"),
        ("replay", "model"),
        ("replay {tmp}/absent.bin", "absent.bin: cannot open"),
        ("replay {tmp}", "is not a regular file"),
        ("replay /dev/zero", "/dev/zero: is not a regular file"),
        ("replay {c}", "not an rdsim model file"),
        ("replay {c} -n 0", "--episodes"),
        ("replay {c} -n -3", "--episodes"),
        ("replay {c} -n 1e9", "--episodes"),
        ("replay {c} --seed -1", "--seed: seed: expected an integer in [0, 2^64 - 1]"),
        ("replay {c} --max-memory -1", "--max-memory"),
        ("bench-fps --runs 0", "--runs"),
        ("bench-fps --steps 0", "--steps"),
        ("bench-fps --steps 1e30", "--steps"),
        ("bench-fps --image-size 5000", "--image-size"),
        ("bench-fps --mode rgb", "--mode"),
        ("render --env jaka_button", "--out"),
        ("render --env jaka_button --out {tmp}/x.png --width 0", "--width"),
        ("render --env jaka_button --out {tmp}/x.png --height 99999", "--height"),
        ("render --env jaka_button --out {tmp}/x.png --view 3", "--view"),
        ("render --env nope --out {tmp}/x.png", "unknown environment \"nope\""),
        ("render --env cartpole --out {tmp}/x.png", "cartpole"),
        ("render --env jaka_button --out {tmp}/x.png --seed -2", "--seed: seed: expected an integer"),
        ("envs --bogus", "bogus"),
    ]:
        cases.append(("cli", "-", args.replace("{c}", c), expected))


# URDF cases: (name, asset it replaces, function of the original text -> malformed text, expected)
def gen_urdfs():
    jaka_path = os.path.join(ROOT, "assets", "jaka", "jaka_zu7.urdf")
    with open(jaka_path, encoding="utf-8") as f:
        jaka = f.read()
    with open(os.path.join(ROOT, "assets", "objects", "button.urdf"), encoding="utf-8") as f:
        button = f.read()

    def first_link_after(text, tag):
        return text

    def replace_once(text, old, new):
        assert old in text, old
        return text.replace(old, new, 1)

    # The first moving link's <mass> / <inertia> and the first revolute joint's <limit>.
    import re
    masses = [m for m in re.finditer(r'<mass value="([^"]*)"\s*/>', jaka)]
    inertias = [m for m in re.finditer(r"<inertia [^>]*/>", jaka)]
    limits = [m for m in re.finditer(r"<limit [^>]*/>", jaka)]
    origins = [m for m in re.finditer(r'<origin xyz="[^"]*" rpy="[^"]*"\s*/>', jaka)]
    axes = [m for m in re.finditer(r'<axis xyz="[^"]*"\s*/>', jaka)]
    boxes = [m for m in re.finditer(r"<(box|cylinder|sphere) [^>]*/>", jaka)]

    def at(match, new):
        return jaka[: match.start()] + new + jaka[match.end():]

    m1, i1, l1 = masses[1], inertias[1], limits[0]
    out = []
    for val, exp in [("nan", "mass [nan] is not a float"), ("inf", "mass [inf] is not a float"), ("-1", "mass -1"), ("0", "movable joint needs a mass > 0"),
                     ("1e9", "out of range"), ("abc", "not a valid URDF")]:
        out.append(("mass-" + val, "jaka/jaka_zu7.urdf", at(m1, '<mass value="%s"/>' % val), exp))
    for attrs, tag, exp in [('ixx="nan" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"', "ixx-nan", "not a valid URDF"),
                            ('ixx="-1" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"', "ixx-negative", "ixx -1"),
                            ('ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"', "all-zero", "not positive definite"),
                            ('ixx="1e30" ixy="0" ixz="0" iyy="1e30" iyz="0" izz="1e30"', "1e30", "implausible"),
                            ('ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="3"', "triangle", "triangle inequality"),
                            ('ixx="0.01" ixy="0.5" ixz="0" iyy="0.01" iyz="0" izz="0.01"', "not-pd", "not positive definite"),
                            ('ixx="inf" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"', "inf", "not a valid URDF"),
                            ('ixx="0.01" ixy="nan" ixz="0" iyy="0.01" iyz="0" izz="0.01"', "ixy-nan", "not a valid URDF")]:
        out.append(("inertia-" + tag, "jaka/jaka_zu7.urdf", at(i1, "<inertia %s/>" % attrs), exp))
    for attrs, tag, exp in [('lower="nan" upper="1" effort="10" velocity="1"', "lower-nan", "lower value (nan) is not a valid float"),
                            ('lower="-1" upper="inf" effort="10" velocity="1"', "upper-inf", "upper value (inf) is not a valid float"),
                            ('lower="2" upper="-2" effort="10" velocity="1"', "lower-above-upper", "lower <= upper"),
                            ('lower="-1" upper="1" effort="0" velocity="1"', "effort-zero", "effort> 0"),
                            ('lower="-1" upper="1" effort="inf" velocity="1"', "effort-inf", "effort value (inf) is not a valid float"),
                            ('lower="-1" upper="1" effort="nan" velocity="1"', "effort-nan", "effort value (nan) is not a valid float"),
                            ('lower="-1" upper="1" effort="10" velocity="-1"', "velocity-negative", "velocity> -1"),
                            ('lower="-1" upper="1" effort="10" velocity="inf"', "velocity-inf", "velocity value (inf) is not a valid float"),
                            ('lower="-1" upper="1" effort="10"', "velocity-missing", "velocity")]:
        out.append(("limit-" + tag, "jaka/jaka_zu7.urdf", at(l1, "<limit %s/>" % attrs), exp))
    out.append(("limit-missing", "jaka/jaka_zu7.urdf", at(l1, ""), "limit"))
    out.append(("origin-nan", "jaka/jaka_zu7.urdf", at(origins[0], '<origin xyz="nan 0 0" rpy="0 0 0"/>'), "not a valid URDF"))
    out.append(("origin-rpy-inf", "jaka/jaka_zu7.urdf", at(origins[0], '<origin xyz="0 0 0" rpy="inf 0 0"/>'), "not a valid URDF"))
    out.append(("axis-zero", "jaka/jaka_zu7.urdf", at(axes[0], '<axis xyz="0 0 0"/>'), "<axis> must be finite and not zero"))
    out.append(("axis-nan", "jaka/jaka_zu7.urdf", at(axes[0], '<axis xyz="nan 0 1"/>'), "not a valid URDF"))
    b = boxes[0]
    shape = b.group(1)
    bad_shapes = {"box": ('<box size="0 0.1 0.1"/>', '<box size="nan 1 1"/>', '<box size="inf 1 1"/>'),
                  "cylinder": ('<cylinder radius="0" length="0.1"/>', '<cylinder radius="nan" length="1"/>',
                               '<cylinder radius="1" length="inf"/>'),
                  "sphere": ('<sphere radius="0"/>', '<sphere radius="nan"/>', '<sphere radius="inf"/>')}[shape]
    for k, text in enumerate(bad_shapes):
        expected = "must be finite and positive" if k == 0 else "jaka_zu7.urdf"
        out.append(("shape-%s-%d" % (shape, k), "jaka/jaka_zu7.urdf", at(b, text), expected))
    out.append(("mesh", "jaka/jaka_zu7.urdf", at(b, '<mesh filename="arm.stl"/>'), 'mesh "arm.stl": file not found (searched: '))
    for ext in ("stl", "obj", "dae", "ply"):  # the URDFs of the mesh cases (gen_meshes)
        out.append(("jaka-mesh-" + ext, None, at(b, '<mesh filename="mesh.%s" scale="0.1 0.1 0.1"/>' % ext), None))
    out.append(("joint-floating", "jaka/jaka_zu7.urdf", replace_once(jaka, 'type="revolute"', 'type="floating"'),
                "floating joints are not supported"))
    out.append(("joint-planar", "jaka/jaka_zu7.urdf", replace_once(jaka, 'type="revolute"', 'type="planar"'),
                "planar joints are not supported"))
    out.append(("joint-unknown-type", "jaka/jaka_zu7.urdf", replace_once(jaka, 'type="revolute"', 'type="hinge"'),
                "not a valid URDF"))
    out.append(("empty", "jaka/jaka_zu7.urdf", "", "not a valid URDF"))
    out.append(("not-xml", "jaka/jaka_zu7.urdf", "this is not XML at all", "not a valid URDF"))
    out.append(("truncated", "jaka/jaka_zu7.urdf", jaka[: len(jaka) // 2], "not a valid URDF"))
    out.append(("no-robot-tag", "jaka/jaka_zu7.urdf", "<?xml version=\"1.0\"?><model/>", "not a valid URDF"))
    out.append(("binary", "jaka/jaka_zu7.urdf", "".join(chr(c) for c in range(1, 256)) * 4, "not a valid URDF"))
    out.append(("deep-xml", "jaka/jaka_zu7.urdf", "<robot name=\"x\">" + "<a>" * 30000 + "</a>" * 30000 + "</robot>",
                "jaka_zu7.urdf"))
    out.append(("missing-link", "jaka/jaka_zu7.urdf", re.sub(r"<link name=\"[^\"]*\">.*?</link>", "", jaka, count=2, flags=re.S),
                "jaka_zu7.urdf"))
    out.append(("link-renamed", "jaka/jaka_zu7.urdf", re.sub(r'<link name="([^"]*)"', r'<link name="\1_x"', jaka, count=1),
                "jaka_zu7.urdf"))
    # one link with two parents: duplicate the last joint under another name and parent
    joints = list(re.finditer(r"<joint .*?</joint>", jaka, flags=re.S))
    dup = joints[-1].group(0).replace('name="', 'name="dup_', 1)
    out.append(("two-parents", "jaka/jaka_zu7.urdf", jaka.replace("</robot>", dup + "</robot>"), "jaka_zu7.urdf"))
    out.append(("rgba-out-of-range", "objects/button.urdf", re.sub(r'rgba="[^"]*"', 'rgba="2 0 0 1"', button, count=1),
                "malformed color rgba"))
    out.append(("button-mass-inf", "objects/button.urdf", re.sub(r'<mass value="[^"]*"\s*/>', '<mass value="inf"/>', button, count=1),
                "mass [inf] is not a float"))
    out.append(("button-empty", "objects/button.urdf", "", "not a valid URDF"))
    out.append(("button-box-nan", "objects/button.urdf",
                re.sub(r"<(box|cylinder) [^>]*/>", '<box size="0 1 1"/>', button, count=1), "must be finite and positive"))
    for name, target, text, expected in out:
        path = os.path.join("urdfs", name + ".urdf")
        with open(os.path.join(OUT, path), "w", encoding="utf-8", newline="") as f:
            f.write(text)
        if target:
            cases.append(("urdf", path, target, expected))


# Mesh cases: (file name, bytes, expected). Each is read as the Jaka base link's visual mesh.
def gen_meshes():
    import struct

    def binary_stl(triangles, count=None):
        out = b"rdsim malformed corpus".ljust(80, b" ") + struct.pack("<I", len(triangles) if count is None else count)
        for tri in triangles:
            out += struct.pack("<3f", 0, 0, 1) + b"".join(struct.pack("<3f", *v) for v in tri) + b"\0\0"
        return out

    tri = ((0, 0, 0), (1, 0, 0), (0, 1, 0))
    dae_head = b'<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">'
    dae_geometry = (b'<library_geometries><geometry id="g"><mesh><source id="p"><float_array id="a" count="%d">%s</float_array>'
                    b'<technique_common><accessor source="#a" count="%d" stride="3"><param name="X" type="float"/>'
                    b'<param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>'
                    b'<vertices id="v"><input semantic="POSITION" source="#p"/></vertices><triangles count="1">'
                    b'<input semantic="VERTEX" source="#v" offset="0"/><p>%s</p></triangles></mesh></geometry></library_geometries>'
                    b'<library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#g"/></node></visual_scene>'
                    b'</library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>')
    cases_ = [
        ("stl-empty.stl", b"", "empty file"),
        ("stl-text.stl", b"this is not a mesh\n", "not a readable STL file"),
        ("stl-ascii-truncated.stl", b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0", "not a readable STL file"),
        ("stl-ascii-no-facets.stl", b"solid x\nendsolid x\n", "not a readable STL file"),
        ("stl-binary-count-too-big.stl", binary_stl([tri], count=1000), "not a readable STL file"),
        ("stl-binary-nan.stl", binary_stl([((float("nan"), 0, 0), (1, 0, 0), (0, 1, 0))]), "not finite"),
        ("stl-binary-huge.stl", binary_stl([((1e30, 0, 0), (1, 0, 0), (0, 1, 0))]), "beyond 1000 m"),
        ("stl-random-bytes.stl", bytes((i * 151 + 7) % 256 for i in range(3000)), "not a readable STL file"),
        ("obj-empty.obj", b"", "empty file"),
        ("obj-vertices-only.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "not a readable OBJ file"),
        ("obj-index-out-of-range.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "vertex index out of range"),
        ("obj-nan.obj", b"v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "not finite"),
        ("obj-lines-only.obj", b"v 0 0 0\nv 1 0 0\nl 1 2\n", "not a readable OBJ file"),
        ("obj-random-bytes.obj", bytes((i * 37 + 11) % 256 for i in range(3000)), "not a readable OBJ file"),
        ("dae-empty.dae", b"", "empty file"),
        ("dae-not-xml.dae", b"this is not XML", "not a readable DAE file"),
        ("dae-truncated.dae", dae_head + b"<library_geometries><geometry", "not a readable DAE file"),
        ("dae-other-xml.dae", b'<?xml version="1.0"?><svg></svg>', "not a readable DAE file"),
        ("dae-no-geometry.dae", dae_head + b"</COLLADA>", "not a readable DAE file"),
        ("dae-count-mismatch.dae", dae_head + dae_geometry % (90, b"0 0 0 1 0 0 0 1 0", 30, b"0 1 2"), "not a readable DAE file"),
        ("dae-index-out-of-range.dae", dae_head + dae_geometry % (9, b"0 0 0 1 0 0 0 1 0", 3, b"0 1 7"), "not a readable DAE file"),
        ("dae-stray-byte-in-p.dae", dae_head + dae_geometry % (9, b"0 0 0 1 0 0 0 1 0", 3, b"0 1!2"), "where integers are expected"),
        ("dae-count-huge.dae", dae_head + dae_geometry % (99999999999, b"0 0 0 1 0 0 0 1 0", 3, b"0 1 2"), "count over"),
        ("ply-unsupported.ply", b"ply\nformat ascii 1.0\nend_header\n", 'unsupported mesh format ".ply"'),
    ]
    for name, data, expected in cases_:
        path = os.path.join("meshes", name)
        with open(os.path.join(OUT, path), "wb") as f:
            f.write(data)
        cases.append(("mesh", path, "jaka/mesh." + name.rsplit(".", 1)[1], expected))


def main():
    for sub in ("configs", "urdfs", "meshes"):
        shutil.rmtree(os.path.join(OUT, sub), ignore_errors=True)
        os.makedirs(os.path.join(OUT, sub))
    gen_configs()
    gen_urdfs()
    gen_meshes()
    gen_cli()
    with open(os.path.join(OUT, "cases.tsv"), "w", encoding="utf-8") as f:
        f.write("# kind\tinput\ttarget\texpected  (written by tools/gen_malformed_corpus.py)\n")
        for kind, inp, target, expected in cases:
            assert "\t" not in target and "\t" not in expected
            f.write("%s\t%s\t%s\t%s\n" % (kind, inp, target, expected))
    print("%d cases" % len(cases))


if __name__ == "__main__":
    main()

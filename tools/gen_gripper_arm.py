#!/usr/bin/env python3
"""Writes assets/jaka/jaka_zu7_gripper.urdf: the JAKA Zu 7 with rdsim's parallel gripper on its flange.

    python3 tools/gen_gripper_arm.py           # (re)write it from the two hand-written files
    python3 tools/gen_gripper_arm.py --check   # only tell whether the committed file is up to date
                                               # (exit 1 if it differs from what would be written)

A development tool (Python 3 standard library only); rdsim never runs it. The sources are
assets/jaka/jaka_zu7.urdf (the arm) and assets/grippers/parallel_gripper_85.urdf (the gripper);
edit those, never the output. The output is the arm, the gripper's materials next to the arm's,
then the gripper's links and joints, joined by one fixed joint `gripper_mount` from the arm's
`flange_link` to the gripper's `gripper_base` with an identity origin: the flange frame's z is the
tool axis out of the flange face, and so is gripper_base's (see both files' header comments).

Attribute values are copied as written (no number reformatting) and the layout is fixed (two
spaces per level, one-line <geometry>/<material>, a blank line between links and joints), so the
output is byte-for-byte deterministic and `--check` can compare it with the committed file.
"""
import argparse
import difflib
import math
import os
import sys
import textwrap
import xml.etree.ElementTree as ET
from xml.sax.saxutils import quoteattr

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ARM_PATH = os.path.join(ROOT, "assets", "jaka", "jaka_zu7.urdf")
GRIPPER_PATH = os.path.join(ROOT, "assets", "grippers", "parallel_gripper_85.urdf")
OUT_PATH = os.path.join(ROOT, "assets", "jaka", "jaka_zu7_gripper.urdf")

ROBOT_NAME = "jaka_zu7_gripper"
FLANGE_LINK = "flange_link"
GRIPPER_ROOT = "gripper_base"
MOUNT_JOINT = "gripper_mount"
EFFECTOR_LINK = "gripper_tcp"


def rel(path):
    return os.path.relpath(path, ROOT)


def fail(message):
    sys.exit(f"gen_gripper_arm: {message}")


# ----------------------------------------------------------------------------------------------
# Reading: the robot element with its comments, and the comments before it (the file's header).

class _Builder:
    """XMLParser target: a TreeBuilder that keeps comments, noting those outside the root."""

    def __init__(self):
        self.tree = ET.TreeBuilder(insert_comments=True)
        self.depth = 0
        self.header = []

    def start(self, tag, attrs):
        self.depth += 1
        return self.tree.start(tag, attrs)

    def end(self, tag):
        self.depth -= 1
        return self.tree.end(tag)

    def data(self, text):
        return self.tree.data(text)

    def comment(self, text):
        if self.depth == 0:
            self.header.append(text)
            return None
        return self.tree.comment(text)

    def close(self):
        return self.tree.close()


def read_urdf(path):
    """(header comments, <robot> element) of one URDF file."""
    builder = _Builder()
    parser = ET.XMLParser(target=builder)
    try:
        with open(path, "rb") as f:
            parser.feed(f.read())
        robot = parser.close()
    except (OSError, ET.ParseError) as e:
        fail(f"{rel(path)}: {e}")
    if robot.tag != "robot":
        fail(f"{rel(path)}: root element is <{robot.tag}>, not <robot>")
    if not builder.header:
        fail(f"{rel(path)}: has no header comment to carry into the output")
    return builder.header, robot


# ----------------------------------------------------------------------------------------------
# Checks on the combined model.

def elements(robot, tag):
    return [e for e in robot if e.tag == tag]


def floats(text, default="0 0 0"):
    return tuple(float(x) for x in (text or default).split())


def rot_rpy(r, p, y):
    """URDF convention: R = Rz(y) * Ry(p) * Rx(r)."""
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return ((cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
            (sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
            (-sp, cp * sr, cp * cr))


def mat_mul(a, b):
    return tuple(tuple(sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)) for i in range(3))


def mat_vec(m, v):
    return tuple(sum(m[i][k] * v[k] for k in range(3)) for i in range(3))


def check_model(robot):
    """Unique names, joints naming existing links, a tree with the arm's base as its one root,
    and the effector reachable from the flange. Returns facts for the header."""
    links = [e.get("name") for e in elements(robot, "link")]
    joints = elements(robot, "joint")
    for kind, names in (("link", links), ("joint", [j.get("name") for j in joints])):
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            fail(f"{kind} names used by both files: {', '.join(dup)}")
    parent_of = {}
    for j in joints:
        parent, child = j.find("parent").get("link"), j.find("child").get("link")
        for end in (parent, child):
            if end not in links:
                fail(f"joint {j.get('name')} names missing link {end!r}")
        if child in parent_of:
            fail(f"link {child} has two parent joints ({parent_of[child].get('name')}, {j.get('name')})")
        parent_of[child] = j
    roots = [n for n in links if n not in parent_of]
    if len(roots) != 1:
        fail(f"expected one root link, found {', '.join(roots) or 'none (a cycle)'}")
    if EFFECTOR_LINK not in links:
        fail(f"effector link {EFFECTOR_LINK} missing")
    # The effector's pose in the flange frame (every joint between them at zero).
    chain, link = [], EFFECTOR_LINK
    while link != FLANGE_LINK:
        if link not in parent_of:
            fail(f"{EFFECTOR_LINK} does not hang off {FLANGE_LINK}")
        chain.append(parent_of[link])
        link = parent_of[link].find("parent").get("link")
    rot, pos = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)), (0.0, 0.0, 0.0)
    for j in reversed(chain):
        origin = j.find("origin")
        xyz = floats(origin.get("xyz") if origin is not None else None)
        rpy = floats(origin.get("rpy") if origin is not None else None)
        pos = tuple(a + b for a, b in zip(pos, mat_vec(rot, xyz)))
        rot = mat_mul(rot, rot_rpy(*rpy))
    return {
        "root": roots[0],
        "movable": [j.get("name") for j in joints if j.get("type") != "fixed"],
        "effector_xyz": pos,
        "effector_z": tuple(row[2] for row in rot),
    }


def total_mass(robot):
    return sum(float(e.find("inertial/mass").get("value")) for e in elements(robot, "link")
               if e.find("inertial/mass") is not None)


# ----------------------------------------------------------------------------------------------
# Combining and writing.

def combine(arm, gripper):
    """The output <robot>: arm materials, gripper materials, arm links/joints, the mount joint,
    gripper links/joints (each file's order and inner comments kept)."""
    if gripper.get("name") is None or arm.get("name") is None:
        fail("both files' <robot> need a name")
    roots = {e.get("name") for e in elements(gripper, "link")} - \
        {j.find("child").get("link") for j in elements(gripper, "joint")}
    if roots != {GRIPPER_ROOT}:
        fail(f"{rel(GRIPPER_PATH)}: root link should be {GRIPPER_ROOT}, is {', '.join(sorted(roots))}")
    if FLANGE_LINK not in {e.get("name") for e in elements(arm, "link")}:
        fail(f"{rel(ARM_PATH)}: no {FLANGE_LINK} to mount the gripper on")

    colours = {}
    for src, robot in ((ARM_PATH, arm), (GRIPPER_PATH, gripper)):
        for m in elements(robot, "material"):
            colour = m.find("color")
            rgba = colour.get("rgba") if colour is not None else None
            if m.get("name") in colours and colours[m.get("name")] != rgba:
                fail(f"{rel(src)}: material {m.get('name')} already defined with another colour")
            colours[m.get("name")] = rgba

    out = ET.Element("robot", {"name": ROBOT_NAME})
    out.extend(elements(arm, "material"))
    out.extend(m for m in elements(gripper, "material") if m.get("name") not in
               {a.get("name") for a in elements(arm, "material")})
    out.extend(e for e in arm if e.tag != "material")
    out.append(ET.Comment(f" The gripper, from {rel(GRIPPER_PATH)}, on the flange. "))
    mount = ET.SubElement(out, "joint", {"name": MOUNT_JOINT, "type": "fixed"})
    ET.SubElement(mount, "origin", {"xyz": "0 0 0", "rpy": "0 0 0"})
    ET.SubElement(mount, "parent", {"link": FLANGE_LINK})
    ET.SubElement(mount, "child", {"link": GRIPPER_ROOT})
    out.extend(e for e in gripper if e.tag != "material")
    return out


def comment(text):
    if "--" in text or text.endswith("-"):
        fail(f"a comment cannot contain '--' or end in '-': {text.strip()[:60]!r}")
    return f"<!--{text}-->"


def is_leaf(e):
    return e.tag is not ET.Comment and len(e) == 0


def write_element(e, depth, lines):
    pad = "  " * depth
    if e.tag is ET.Comment:
        lines.append(f"{pad}{comment(e.text)}")
        return
    if e.text and e.text.strip():
        fail(f"<{e.tag}> has text content {e.text.strip()!r}, which this tool does not carry")
    attrs = "".join(f" {k}={quoteattr(v)}" for k, v in e.attrib.items())
    if len(e) == 0:
        lines.append(f"{pad}<{e.tag}{attrs}/>")
    elif len(e) == 1 and is_leaf(e[0]):
        inner = []
        write_element(e[0], 0, inner)
        lines.append(f"{pad}<{e.tag}{attrs}>{inner[0]}</{e.tag}>")
    else:
        lines.append(f"{pad}<{e.tag}{attrs}>")
        for child in e:
            write_element(child, depth + 1, lines)
        lines.append(f"{pad}</{e.tag}>")


def render(arm_header, gripper_header, robot, facts, arm_mass, gripper_mass):
    nb = "\N{NO-BREAK SPACE}"  # keeps a vector or a command on one line through textwrap
    xyz = f",{nb}".join(f"{round(v, 6) + 0.0:g}" for v in facts["effector_xyz"])
    ax = nb.join(f"{round(v, 6) + 0.0:g}" for v in facts["effector_z"])
    movable = facts["movable"]
    paragraphs = (
        f"GENERATED by tools/gen_gripper_arm.py from {rel(ARM_PATH)} and {rel(GRIPPER_PATH)}: "
        f"edit those two files, then run `python3{nb}tools/gen_gripper_arm.py` (its check option tells "
        f"whether this file is up to date).",
        f"The JAKA Zu 7 arm with rdsim's parallel-jaw gripper (a Robotiq 2F-85 stand-in) bolted to its "
        f"tool flange: the fixed joint {MOUNT_JOINT} puts {GRIPPER_ROOT}'s frame on {FLANGE_LINK}'s "
        f"(identity origin), so the flange's z, the tool axis, points from the flange face to the "
        f"fingertips. Root link {facts['root']} (fix it to the world). {len(movable)} movable joints: "
        f"{', '.join(movable)}. Effector link for tasks: {EFFECTOR_LINK}, the centre between the finger "
        f"pads, at ({xyz}) in the {FLANGE_LINK} frame with its z axis along ({ax}) there. "
        f"Masses: arm {arm_mass:g} kg, gripper {gripper_mass:g} kg.",
        "The two source files' header comments follow.",
    )
    summary = "\n" + "\n\n".join(textwrap.fill(p, 100, initial_indent="  ", subsequent_indent="  ")
                                    for p in paragraphs).replace(nb, " ") + "\n"
    lines = ['<?xml version="1.0"?>', comment(summary)]
    for path, header in ((ARM_PATH, arm_header), (GRIPPER_PATH, gripper_header)):
        for text in header:
            lines.append(comment(f" From {rel(path)}:{text}"))
    lines.append(f"<robot name={quoteattr(robot.get('name'))}>")
    prev = None
    for child in robot:
        both_materials = prev is not None and prev.tag == child.tag == "material"
        after_comment = prev is not None and prev.tag is ET.Comment
        if prev is not None and not both_materials and not after_comment:
            lines.append("")
        write_element(child, 1, lines)
        prev = child
    lines.append("</robot>")
    return "\n".join(lines) + "\n"


def generate():
    arm_header, arm = read_urdf(ARM_PATH)
    gripper_header, gripper = read_urdf(GRIPPER_PATH)
    arm_mass, gripper_mass = total_mass(arm), total_mass(gripper)
    robot = combine(arm, gripper)
    facts = check_model(robot)
    text = render(arm_header, gripper_header, robot, facts, round(arm_mass, 6), round(gripper_mass, 6))
    return text, facts


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true",
                    help="exit 1 if the committed output differs from what would be generated")
    args = ap.parse_args()
    text, facts = generate()
    if args.check:
        try:
            with open(OUT_PATH, encoding="utf-8") as f:
                committed = f.read()
        except OSError as e:
            print(f"gen_gripper_arm: {rel(OUT_PATH)} cannot be read ({e.strerror}); "
                  f"run python3 tools/gen_gripper_arm.py", file=sys.stderr)
            sys.exit(1)
        if committed != text:
            diff = list(difflib.unified_diff(committed.splitlines(), text.splitlines(),
                                             f"{rel(OUT_PATH)} (committed)", "(generated)", lineterm=""))
            print(f"gen_gripper_arm: {rel(OUT_PATH)} is out of date with {rel(ARM_PATH)} / "
                  f"{rel(GRIPPER_PATH)}; run python3 tools/gen_gripper_arm.py. First differences:",
                  file=sys.stderr)
            print("\n".join(diff[:30]), file=sys.stderr)
            sys.exit(1)
        print(f"{rel(OUT_PATH)}: up to date ({len(facts['movable'])} movable joints)")
        return
    with open(OUT_PATH, "w", encoding="utf-8", newline="\n") as f:
        f.write(text)
    print(f"wrote {rel(OUT_PATH)}: {len(facts['movable'])} movable joints, effector {EFFECTOR_LINK} at "
          f"{tuple(round(v, 6) + 0.0 for v in facts['effector_xyz'])} in {FLANGE_LINK}")


if __name__ == "__main__":
    main()

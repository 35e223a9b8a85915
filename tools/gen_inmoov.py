#!/usr/bin/env python3
"""Writes rdsim's InMoov tomato-task assets from the numbers in this file.

    python3 tools/gen_inmoov.py            # (re)write assets/inmoov/inmoov.urdf and
                                           # assets/objects/tomato_tree.urdf, then check them
    python3 tools/gen_inmoov.py --check    # only re-read the committed files and check them
    python3 tools/gen_inmoov.py --table    # markdown joint table for assets/README.md

A development tool (Python 3 standard library only); rdsim never runs it. The robot and the tree
come from one script so that "every tomato is within reach of the right hand" is checked here,
from forward kinematics of the generated robot, not merely claimed in a README.

Conventions (see assets/README.md): the robot faces +x, z is up, the root link `base_link` sits
on the floor at the world origin and is meant to be fixed to the world. Every link's geometry is
axis-aligned in the link's own frame (only translations in visual/collision/inertial origins), so
any URDF loader reads the same inertia tensors; rotations live in joint origins only.
"""
import argparse
import math
import os
import sys
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
INMOOV_PATH = os.path.join(ROOT, "assets", "inmoov", "inmoov.urdf")
TREE_PATH = os.path.join(ROOT, "assets", "objects", "tomato_tree.urdf")

# Where the tomato tree's root frame is meant to stand in the robot's world frame (unrotated).
TREE_WORLD_XYZ = (0.65, -0.20, 0.0)
# A tomato counts as reachable by construction when its centre is within this distance of the
# right shoulder (the palm centre reaches about 0.59 m with the arm straight) and in front of the
# chest's front face.
REACH_LIMIT = 0.55
MIN_TOMATO_X = 0.25

# Colours (rgba). White printed PLA, dark servo/joint housings.
COLOURS = {
    "white_pla": (0.92, 0.92, 0.89, 1.0),
    "dark_joint": (0.16, 0.16, 0.18, 1.0),
    "pedestal_grey": (0.35, 0.35, 0.37, 1.0),
    "eye_black": (0.05, 0.05, 0.06, 1.0),
    "pot_terracotta": (0.62, 0.33, 0.20, 1.0),
    "stem_green": (0.20, 0.45, 0.12, 1.0),
    "branch_green": (0.30, 0.62, 0.18, 1.0),
    "tomato_red": (0.85, 0.08, 0.05, 1.0),
}


# ----------------------------------------------------------------------------------------------
# Small rotation maths (3-vectors as tuples, 3x3 matrices as tuples of rows).

def rot_rpy(r, p, y):
    """URDF convention: R = Rz(y) * Ry(p) * Rx(r)."""
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return ((cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
            (sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
            (-sp, cp * sr, cp * cr))


def rpy_of(m):
    p = math.asin(max(-1.0, min(1.0, -m[2][0])))
    return (math.atan2(m[2][1], m[2][2]), p, math.atan2(m[1][0], m[0][0]))


def mat_mul(a, b):
    return tuple(tuple(sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)) for i in range(3))


def mat_vec(m, v):
    return tuple(sum(m[i][k] * v[k] for k in range(3)) for i in range(3))


def transpose(m):
    return tuple(tuple(m[j][i] for j in range(3)) for i in range(3))


def add(a, b):
    return tuple(x + y for x, y in zip(a, b))


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def scale(v, s):
    return tuple(x * s for x in v)


def norm(v):
    return math.sqrt(sum(x * x for x in v))


def rot_axis(a, angle):
    """Rotation by `angle` about the unit vector a (Rodrigues)."""
    c, s, t = math.cos(angle), math.sin(angle), 1 - math.cos(angle)
    x, y, z = a
    return ((t * x * x + c, t * x * y - s * z, t * x * z + s * y),
            (t * x * y + s * z, t * y * y + c, t * y * z - s * x),
            (t * x * z - s * y, t * y * z + s * x, t * z * z + c))


IDENTITY = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


# ----------------------------------------------------------------------------------------------
# Model description: plain data, turned into XML at the end.

class Shape:
    """One primitive; `xyz` is its centre in the link frame; cylinders run along the link's z."""

    def __init__(self, kind, dims, xyz=(0.0, 0.0, 0.0)):
        self.kind, self.dims, self.xyz = kind, tuple(dims), tuple(xyz)

    def principal_inertia(self, mass):
        """Solid-body inertia about the shape's centre (the textbook formulas)."""
        if self.kind == "box":
            x, y, z = self.dims
            return (mass * (y * y + z * z) / 12, mass * (x * x + z * z) / 12, mass * (x * x + y * y) / 12)
        if self.kind == "cylinder":
            r, h = self.dims
            side = mass * (3 * r * r + h * h) / 12
            return (side, side, mass * r * r / 2)
        (r,) = self.dims
        i = 2 * mass * r * r / 5
        return (i, i, i)

    def volume(self):
        if self.kind == "box":
            return self.dims[0] * self.dims[1] * self.dims[2]
        if self.kind == "cylinder":
            return math.pi * self.dims[0] ** 2 * self.dims[1]
        return 4 / 3 * math.pi * self.dims[0] ** 3

    def bounding_radius(self):
        if self.kind == "box":
            return norm(self.dims) / 2
        if self.kind == "cylinder":
            return math.hypot(self.dims[0], self.dims[1] / 2)
        return self.dims[0]


def box(sx, sy, sz, xyz=(0, 0, 0)):
    return Shape("box", (sx, sy, sz), xyz)


def cylinder(r, length, xyz=(0, 0, 0)):
    return Shape("cylinder", (r, length), xyz)


def sphere(r, xyz=(0, 0, 0)):
    return Shape("sphere", (r,), xyz)


class Link:
    """`shape` carries the mass (inertia from its formula); `collide=False` marks joint housings
    and parts that sit inside another link, which would otherwise touch their neighbours at rest."""

    def __init__(self, name, shape, mass, colour, collide=True, extra_visuals=(), visible=True):
        self.name, self.shape, self.mass, self.colour = name, shape, mass, colour
        self.collide, self.extra_visuals, self.visible = collide, list(extra_visuals), visible


class Joint:
    def __init__(self, name, kind, parent, child, xyz=(0, 0, 0), rpy=(0, 0, 0), axis=None,
                 lower=None, upper=None, effort=None, velocity=None, note=""):
        self.name, self.kind, self.parent, self.child = name, kind, parent, child
        self.xyz, self.rpy, self.axis = tuple(xyz), tuple(rpy), axis
        self.lower, self.upper, self.effort, self.velocity, self.note = lower, upper, effort, velocity, note


class Model:
    def __init__(self, name):
        self.name, self.links, self.joints = name, [], []

    def link(self, *args, **kwargs):
        self.links.append(Link(*args, **kwargs))

    def joint(self, *args, **kwargs):
        self.joints.append(Joint(*args, **kwargs))

    def revolute(self, name, parent, child, xyz, axis, lower_deg, upper_deg, effort, velocity,
                 rpy=(0, 0, 0), note=""):
        self.joint(name, "revolute", parent, child, xyz, rpy, axis, math.radians(lower_deg),
                   math.radians(upper_deg), effort, velocity, note)

    def fixed(self, name, parent, child, xyz, rpy=(0, 0, 0)):
        self.joint(name, "fixed", parent, child, xyz, rpy)


def deg(x):
    return math.radians(x)


# ----------------------------------------------------------------------------------------------
# InMoov. Numbers in metres, kilograms, N*m, rad/s. Masses are estimates for a robot printed in
# PLA at roughly 20-30 % infill (effective density ~400-700 kg/m^3) carrying its hobby servos
# (MG996R ~55 g for fingers/wrist/jaw/eyes, HS-805BB ~150 g for shoulders/elbows/neck/torso);
# assets/README.md lists them.

PEDESTAL_TOP = 0.80      # hips rest on a 0.80 m stand
HIPS_HEIGHT = 0.10
STOMACH_HEIGHT = 0.10
SHOULDER_ABOVE_CHEST_JOINT = 0.30   # -> shoulders at 0.80 + 0.10 + 0.10 + 0.30 = 1.30 m
CHEST_HEIGHT = 0.34
SHOULDER_Y = 0.20        # shoulder joint centres 0.40 m apart
UPPER_ARM = 0.28
FOREARM = 0.26
PALM_LENGTH = 0.10       # wrist to knuckles; + 0.09 middle finger = 0.19 m hand
PALM_WIDTH = 0.085
PALM_THICKNESS = 0.03

# (name, knuckle x on the palm, phalanx lengths proximal/middle/distal, radius)
FINGERS = (
    ("index", 0.030, (0.040, 0.024, 0.018), 0.0085),
    ("middle", 0.010, (0.044, 0.027, 0.019), 0.0090),
    ("ring", -0.010, (0.041, 0.026, 0.018), 0.0085),
    ("pinky", -0.030, (0.032, 0.019, 0.016), 0.0075),
)
THUMB = (0.044, 0.032, 0.027)  # metacarpal, proximal, distal
THUMB_RADIUS = 0.010
THUMB_TILT = 0.55              # rad: the thumb points forward-down from the palm's front edge
FINGER_DENSITY = 900.0         # kg/m^3: small printed phalanges are nearly solid, plus tendons


def add_torso_and_head(m):
    m.link("base_link", box(0.26, 0.26, PEDESTAL_TOP, (0, 0, PEDESTAL_TOP / 2)), 8.0, "pedestal_grey")
    m.link("hips", box(0.24, 0.28, HIPS_HEIGHT, (0, 0, HIPS_HEIGHT / 2)), 1.5, "white_pla")
    m.fixed("hips_fixed", "base_link", "hips", (0, 0, PEDESTAL_TOP))

    m.link("stomach", box(0.18, 0.24, STOMACH_HEIGHT - 0.01, (0, 0, STOMACH_HEIGHT / 2)), 1.2, "white_pla")
    m.revolute("mid_stomach", "hips", "stomach", (0, 0, HIPS_HEIGHT), (0, 0, 1), -40, 40, 25.0, 1.0,
               note="torso yaw, + turns left")
    m.link("chest", box(0.20, 0.28, CHEST_HEIGHT - 0.01, (0, 0, 0.005 + CHEST_HEIGHT / 2)), 4.0, "white_pla")
    m.revolute("top_stomach", "stomach", "chest", (0, 0, STOMACH_HEIGHT), (1, 0, 0), -30, 30, 25.0, 1.0,
               note="torso side bend (roll), + leans right")

    # Neck: yaw at the chest top, then pitch and roll in one gimbal 6 cm higher.
    m.link("neck", cylinder(0.035, 0.05, (0, 0, 0.03)), 0.20, "dark_joint")
    m.revolute("neck_yaw", "chest", "neck", (0, 0, CHEST_HEIGHT), (0, 0, 1), -70, 70, 4.0, 2.0,
               note="+ looks left")
    m.link("neck_gimbal", sphere(0.03), 0.08, "dark_joint", collide=False)
    m.revolute("neck_pitch", "neck", "neck_gimbal", (0, 0, 0.06), (0, 1, 0), -50, 45, 4.0, 2.0,
               note="+ looks down")
    m.link("head", box(0.19, 0.16, 0.19, (0.01, 0, 0.135)), 1.3, "white_pla")
    m.revolute("neck_roll", "neck_gimbal", "head", (0, 0, 0), (1, 0, 0), -30, 30, 4.0, 2.0,
               note="+ tilts the head to its right")
    m.link("jaw", box(0.08, 0.11, 0.025, (0.04, 0, -0.0125)), 0.12, "white_pla")
    m.revolute("jaw", "head", "jaw", (0.04, 0, 0.035), (0, 1, 0), 0, 25, 1.0, 3.0, note="+ opens")
    # Eyes (InMoov carries a camera in each): pan then tilt; inside the head box, so no collision.
    for side, y in (("l", 0.033), ("r", -0.033)):
        m.link(f"{side}_eye_yoke", sphere(0.012), 0.006, "dark_joint", collide=False)
        m.revolute(f"{side}_eye_pan", "head", f"{side}_eye_yoke", (0.092, y, 0.150), (0, 0, 1), -35, 35,
                   0.2, 6.0, note="+ looks left")
        m.link(f"{side}_eye", sphere(0.013), 0.010, "eye_black", collide=False)
        m.revolute(f"{side}_eye_tilt", f"{side}_eye_yoke", f"{side}_eye", (0, 0, 0), (0, 1, 0), -25, 25,
                   0.2, 6.0, note="+ looks down")


def mirror(side):
    """Left = right mirrored through the x-z plane. A mirrored rotation axis a becomes
    (-ax, ay, -az) so that a positive angle is the same anatomical motion on both sides."""
    if side == "r":
        return (lambda v: tuple(v)), (lambda a: tuple(a)), (lambda r: tuple(r))
    return ((lambda v: (v[0], -v[1], v[2])), (lambda a: (-a[0], a[1], -a[2])),
            (lambda r: (-r[0], r[1], -r[2])))


def add_arm(m, side):
    """Arm hanging along -z in the zero pose, palm facing the body, thumb forward (+x)."""
    P, A, R = mirror(side)
    s = side
    # Three shoulder joints meet at one point, as in a human shoulder.
    m.link(f"{s}_shoulder_blade", sphere(0.055), 0.30, "dark_joint", collide=False)
    m.revolute(f"{s}_omoplate", "chest", f"{s}_shoulder_blade",
               P((0, -SHOULDER_Y, SHOULDER_ABOVE_CHEST_JOINT)), A((-1, 0, 0)), -10, 90, 12.0, 1.5,
               note="abduction: + raises the arm sideways")
    # The shoulder housing collides (it clears the chest by 15 mm): besides being a real surface,
    # rdsim's Bullet world needs a collider on at least one of a joint's two links (see README).
    m.link(f"{s}_shoulder", sphere(0.045), 0.25, "dark_joint")
    m.revolute(f"{s}_shoulder_lift", f"{s}_shoulder_blade", f"{s}_shoulder", (0, 0, 0), A((0, -1, 0)),
               -50, 180, 12.0, 1.5, note="flexion: + raises the arm forward")
    m.link(f"{s}_upper_arm", cylinder(0.045, UPPER_ARM - 0.01, (0, 0, -UPPER_ARM / 2)), 0.70, "white_pla")
    m.revolute(f"{s}_upper_arm_rotate", f"{s}_shoulder", f"{s}_upper_arm", (0, 0, 0), A((0, 0, 1)),
               -90, 70, 6.0, 2.0, note="+ internal rotation")
    m.link(f"{s}_forearm", cylinder(0.040, FOREARM - 0.01, (0, 0, -FOREARM / 2)), 0.65, "white_pla")
    m.revolute(f"{s}_elbow", f"{s}_upper_arm", f"{s}_forearm", (0, 0, -UPPER_ARM), A((0, -1, 0)),
               0, 140, 8.0, 2.0, note="flexion (InMoov 'bicep'): + bends")
    m.link(f"{s}_wrist", sphere(0.03), 0.08, "dark_joint", collide=False)
    m.revolute(f"{s}_wrist_roll", f"{s}_forearm", f"{s}_wrist", (0, 0, -FOREARM), A((0, 0, 1)),
               -85, 85, 2.0, 3.0, note="+ pronation")
    m.link(f"{s}_hand", box(PALM_WIDTH, PALM_THICKNESS, PALM_LENGTH - 0.005,
                             P((0, 0, -(PALM_LENGTH + 0.005) / 2))), 0.20, "white_pla")
    m.revolute(f"{s}_wrist_pitch", f"{s}_wrist", f"{s}_hand", (0, 0, 0), A((1, 0, 0)), -70, 80, 2.0, 3.0,
               note="+ flexion (palm side)")
    # End effector: centre of the palm's face.
    m.link(f"{s}_hand_ee", sphere(0.01), 0.002, "dark_joint", collide=False, visible=False)
    m.fixed(f"{s}_hand_ee_joint", f"{s}_hand", f"{s}_hand_ee",
            P((0, PALM_THICKNESS / 2, -(PALM_LENGTH + 0.005) / 2)))

    # Fingers curl toward the palm face (+y on the right hand): the same axis as wrist flexion.
    curl = A((1, 0, 0))
    limits = ((-15, 90), (0, 110), (0, 80))
    parts = ("proximal", "middle", "distal")
    for name, x, lengths, radius in FINGERS:
        parent, at = f"{s}_hand", P((x, 0, -PALM_LENGTH))
        for i, (length, (lo, hi), part) in enumerate(zip(lengths, limits, parts)):
            child = f"{s}_{name}_{part}"
            shape = cylinder(radius, length - 0.004, (0, 0, -length / 2))
            m.link(child, shape, round(FINGER_DENSITY * shape.volume(), 4), "white_pla")
            m.revolute(f"{s}_{name}_{i + 1}", parent, child, at, curl, lo, hi, 0.6, 4.0,
                       note=("MCP", "PIP", "DIP")[i] + " flexion")
            parent, at = child, (0, 0, -length)

    # Thumb: its base sits on the palm's front edge, tilted forward-down; thumb_0 turns the whole
    # thumb about its own long axis (opposition), thumb_1..3 curl it like the fingers.
    m.link(f"{s}_thumb_base", sphere(0.012), 0.006, "dark_joint", collide=False)
    m.revolute(f"{s}_thumb_0", f"{s}_hand", f"{s}_thumb_base", P((PALM_WIDTH / 2 + 0.010, 0, -0.022)),
               A((0, 0, 1)), 0, 80, 0.6, 4.0, rpy=R((0, -THUMB_TILT, 0)), note="opposition")
    parent, at = f"{s}_thumb_base", (0, 0, -0.006)
    for i, (length, (lo, hi), part) in enumerate(zip(THUMB, ((-15, 50), (0, 60), (-10, 80)),
                                                       ("metacarpal", "proximal", "distal"))):
        child = f"{s}_thumb_{part}"
        shape = cylinder(THUMB_RADIUS, length - 0.004, (0, 0, -length / 2))
        m.link(child, shape, round(FINGER_DENSITY * shape.volume(), 4), "white_pla")
        m.revolute(f"{s}_thumb_{i + 1}", parent, child, at, curl, lo, hi, 0.6, 4.0,
                   note=("CMC", "MCP", "IP")[i] + " flexion")
        parent, at = child, (0, 0, -length)


def build_inmoov():
    m = Model("inmoov")
    add_torso_and_head(m)
    add_arm(m, "r")
    add_arm(m, "l")
    return m


# ----------------------------------------------------------------------------------------------
# Tomato tree: a pot, a trunk, four branches reaching toward the robot (the tree frame's -x) and
# seven tomatoes hanging on short stems. Every tomato is its own link `tomato_<i>` whose frame is
# the tomato's centre, aligned with the tree frame.

TOMATO_RADIUS = 0.035
STEM = 0.05
POT_HEIGHT = 0.20
TRUNK_HEIGHT = 1.50
# One tomato at the tip of each branch: (height where the branch leaves the trunk axis, branch tip
# in the tree frame). Tips point toward the robot (the tree frame's -x); the tomato hangs
# STEM + TOMATO_RADIUS below its tip. Chosen so that, with the tree at TREE_WORLD_XYZ, the
# tomatoes spread over 0.36-0.53 m from the right shoulder, left/right of it and above/below it.
BRANCHES = (
    (1.005, (-0.25, -0.22, 1.135)),
    (0.975, (-0.23, -0.02, 1.105)),
    (1.205, (-0.20, -0.25, 1.335)),
    (1.135, (-0.27, -0.08, 1.265)),
    (1.255, (-0.23, 0.05, 1.385)),
    (1.335, (-0.17, -0.12, 1.465)),
)


def build_tree():
    m = Model("tomato_tree")
    m.link("pot", cylinder(0.12, POT_HEIGHT, (0, 0, POT_HEIGHT / 2)), 8.0, "pot_terracotta")  # with soil
    m.link("trunk", cylinder(0.025, TRUNK_HEIGHT, (0, 0, TRUNK_HEIGHT / 2)), 1.5, "stem_green")
    m.fixed("trunk_fixed", "pot", "trunk", (0, 0, POT_HEIGHT))
    for n, (height, tip) in enumerate(BRANCHES):
        along = sub(tip, (0, 0, height))
        length = norm(along)
        frame = frame_with_z(scale(along, 1 / length))  # branch frame: z from trunk to tip
        name = f"branch_{n}"
        m.link(name, cylinder(0.010, length, (0, 0, length / 2)), 0.08, "branch_green")
        m.fixed(f"{name}_fixed", "trunk", name, (0, 0, height - POT_HEIGHT), rpy_of(frame))
        back = transpose(frame)  # tree axes expressed in the branch frame
        centre = add((0, 0, length), mat_vec(back, (0, 0, -(STEM + TOMATO_RADIUS))))
        stem = cylinder(0.004, STEM, (0, 0, TOMATO_RADIUS + STEM / 2))
        # The tomato's frame is its centre, axes parallel to the tree frame's.
        m.link(f"tomato_{n}", sphere(TOMATO_RADIUS), 0.15, "tomato_red", extra_visuals=[(stem, "stem_green")])
        m.fixed(f"tomato_{n}", name, f"tomato_{n}", centre, rpy_of(back))
    return m


def frame_with_z(z):
    """A rotation whose third column is the unit vector z (x kept horizontal)."""
    x = (z[1], -z[0], 0.0)
    x = scale(x, 1 / norm(x))
    y = (z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0])
    return tuple(tuple((x, y, z)[c][r] for c in range(3)) for r in range(3))


# ----------------------------------------------------------------------------------------------
# XML output.

def fmt(v):
    v = 0.0 if abs(v) < 5e-10 else v
    return f"{v:.9g}"


def vec(v):
    return " ".join(fmt(x) for x in v)


def geometry_xml(parent, shape, colour=None):
    ET.SubElement(parent, "origin", xyz=vec(shape.xyz), rpy="0 0 0")
    geometry = ET.SubElement(parent, "geometry")
    if shape.kind == "box":
        ET.SubElement(geometry, "box", size=vec(shape.dims))
    elif shape.kind == "cylinder":
        ET.SubElement(geometry, "cylinder", radius=fmt(shape.dims[0]), length=fmt(shape.dims[1]))
    else:
        ET.SubElement(geometry, "sphere", radius=fmt(shape.dims[0]))
    if colour:
        material = ET.SubElement(parent, "material", name=colour)
        ET.SubElement(material, "color", rgba=vec(COLOURS[colour]))


def to_xml(model, header):
    robot = ET.Element("robot", name=model.name)
    for link in model.links:
        el = ET.SubElement(robot, "link", name=link.name)
        inertial = ET.SubElement(el, "inertial")
        ET.SubElement(inertial, "origin", xyz=vec(link.shape.xyz), rpy="0 0 0")
        ET.SubElement(inertial, "mass", value=fmt(link.mass))
        ixx, iyy, izz = link.shape.principal_inertia(link.mass)
        ET.SubElement(inertial, "inertia", ixx=fmt(ixx), ixy="0", ixz="0", iyy=fmt(iyy), iyz="0", izz=fmt(izz))
        if link.visible:
            geometry_xml(ET.SubElement(el, "visual"), link.shape, link.colour)
            for shape, colour in link.extra_visuals:
                geometry_xml(ET.SubElement(el, "visual"), shape, colour)
        if link.collide:
            geometry_xml(ET.SubElement(el, "collision"), link.shape)
    for j in model.joints:
        el = ET.SubElement(robot, "joint", name=j.name, type=j.kind)
        ET.SubElement(el, "origin", xyz=vec(j.xyz), rpy=vec(j.rpy))
        ET.SubElement(el, "parent", link=j.parent)
        ET.SubElement(el, "child", link=j.child)
        if j.kind != "fixed":
            ET.SubElement(el, "axis", xyz=vec(j.axis))
            ET.SubElement(el, "limit", lower=fmt(j.lower), upper=fmt(j.upper), effort=fmt(j.effort),
                          velocity=fmt(j.velocity))
    ET.indent(robot, space="  ")
    return f'<?xml version="1.0"?>\n<!-- {header} -->\n' + ET.tostring(robot, encoding="unicode") + "\n"


# ----------------------------------------------------------------------------------------------
# Checks, run on the XML as written (so they also catch a hand edit of the committed files).

class Parsed:
    """The parts of a URDF the checks need, read back from XML."""

    def __init__(self, path):
        self.path = path
        root = ET.parse(path).getroot()
        if root.tag != "robot":
            fail(path, "root element is not <robot>")
        self.links, self.joints = {}, {}
        for el in root.findall("link"):
            name = el.get("name")
            if not name or name in self.links:
                fail(path, f"missing or duplicate link name {name!r}")
            self.links[name] = self.read_link(el)
        for el in root.findall("joint"):
            name = el.get("name")
            if not name or name in self.joints:
                fail(path, f"missing or duplicate joint name {name!r}")
            self.joints[name] = self.read_joint(el)

    def read_link(self, el):
        inertial = el.find("inertial")
        if inertial is None:
            fail(self.path, f"link {el.get('name')} has no <inertial>")
        i = inertial.find("inertia")
        collisions = []
        for c in el.findall("collision"):
            xyz = floats(c.find("origin").get("xyz"))
            g = c.find("geometry")[0]
            dims = {"box": lambda: floats(g.get("size")), "sphere": lambda: (float(g.get("radius")),),
                    "cylinder": lambda: (float(g.get("radius")), float(g.get("length")))}[g.tag]()
            collisions.append(Shape(g.tag, dims, xyz))
        return {"mass": float(inertial.find("mass").get("value")),
                "inertia": tuple(float(i.get(k)) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")),
                "collisions": collisions, "visuals": len(el.findall("visual"))}

    def read_joint(self, el):
        origin = el.find("origin")
        joint = {"name": el.get("name"), "type": el.get("type"), "parent": el.find("parent").get("link"),
                 "child": el.find("child").get("link"),
                 "xyz": floats(origin.get("xyz", "0 0 0")), "rpy": floats(origin.get("rpy", "0 0 0"))}
        limit = el.find("limit")
        if limit is not None:
            joint["limits"] = (float(limit.get("lower")), float(limit.get("upper")))
        if el.find("axis") is not None:
            joint["axis"] = floats(el.find("axis").get("xyz"))
        return joint

    def root(self):
        children = {j["child"] for j in self.joints.values()}
        roots = [name for name in self.links if name not in children]
        if len(roots) != 1:
            fail(self.path, f"expected exactly one root link, found {roots}")
        return roots[0]

    def frame_of(self, link, angles):
        """World frame of one link (root at the origin): only the joints on its path."""
        path = []
        by_child = {j["child"]: j for j in self.joints.values()}
        while link in by_child:
            path.append(by_child[link])
            link = by_child[link]["parent"]
        rot, pos = IDENTITY, (0.0, 0.0, 0.0)
        for j in reversed(path):
            pos = add(pos, mat_vec(rot, j["xyz"]))
            rot = mat_mul(rot, rot_rpy(*j["rpy"]))
            if j["name"] in angles:
                rot = mat_mul(rot, rot_axis(j["axis"], angles[j["name"]]))
        return rot, pos

    def world_frames(self, base_xyz=(0.0, 0.0, 0.0), angles=None):
        """Frame (rotation, position) of every link with the root at base_xyz; joints not named in
        `angles` (joint name -> rad) stay at zero."""
        angles = angles or {}
        frames = {self.root(): (IDENTITY, tuple(base_xyz))}
        pending = list(self.joints.values())
        while pending:
            progressed = [j for j in pending if j["parent"] in frames]
            if not progressed:
                fail(self.path, "joints that do not connect to the root: "
                     + ", ".join(sorted(j["child"] for j in pending)))
            for j in progressed:
                rot, pos = frames[j["parent"]]
                child_rot = mat_mul(rot, rot_rpy(*j["rpy"]))
                if j["name"] in angles:
                    child_rot = mat_mul(child_rot, rot_axis(j["axis"], angles[j["name"]]))
                frames[j["child"]] = (child_rot, add(pos, mat_vec(rot, j["xyz"])))
                pending.remove(j)
        return frames


def floats(text):
    return tuple(float(x) for x in text.split())


def fail(path, message):
    sys.exit(f"{os.path.relpath(path, ROOT)}: {message}")


def check_structure(p):
    """One root, every joint's links exist, each link has at most one parent (a tree), sane
    inertials and limits."""
    parents = {}
    for name, j in p.joints.items():
        for end in ("parent", "child"):
            if j[end] not in p.links:
                fail(p.path, f"joint {name} names missing {end} link {j[end]!r}")
        if j["child"] in parents:
            fail(p.path, f"link {j['child']} has two parent joints ({parents[j['child']]}, {name})")
        parents[j["child"]] = name
        if j["type"] not in ("revolute", "continuous", "prismatic", "fixed"):
            fail(p.path, f"joint {name} has unsupported type {j['type']!r}")
        if j["type"] in ("revolute", "prismatic"):
            lo, hi = j.get("limits", (0.0, 0.0))
            if not lo < hi:
                fail(p.path, f"joint {name} needs lower < upper, has {lo} .. {hi}")
            if abs(norm(j["axis"]) - 1) > 1e-9:
                fail(p.path, f"joint {name} axis is not a unit vector")
    p.world_frames()  # also proves every link hangs off the single root (no cycles)
    for name, link in p.links.items():
        ixx, iyy, izz, *off = link["inertia"]
        if not link["mass"] > 0 or min(ixx, iyy, izz) <= 0 or any(off):
            fail(p.path, f"link {name} needs positive mass and a positive diagonal inertia")
        if ixx + iyy < izz or iyy + izz < ixx or izz + ixx < iyy:
            fail(p.path, f"link {name} inertia breaks the triangle inequality")


def collision_bodies(p, frames, prefix=""):
    """(link name, shape, world rotation, world centre) of every collision shape."""
    bodies = []
    for name, link in p.links.items():
        rot, pos = frames[name]
        for shape in link["collisions"]:
            bodies.append((prefix + name, shape, rot, add(pos, mat_vec(rot, shape.xyz))))
    return bodies


def adjacent_pairs(p, prefix=""):
    return {frozenset((prefix + j["parent"], prefix + j["child"])) for j in p.joints.values()}


def overlapping_pairs(bodies, skip):
    """Pairs of collision shapes, other than the pairs in `skip`, that interpenetrate (so a loader
    that enables self-collision does not start with the robot pushing itself apart). Sampled:
    points on each shape's surface tested for being inside the other, 1 mm slack."""
    found = []
    for a in range(len(bodies)):
        for b in range(a + 1, len(bodies)):
            na, sa, ra, ca = bodies[a]
            nb, sb, rb, cb = bodies[b]
            if na == nb or frozenset((na, nb)) in skip:
                continue
            if norm(sub(ca, cb)) > sa.bounding_radius() + sb.bounding_radius():
                continue
            if any(inside(sb, rb, cb, q) for q in surface_points(sa, ra, ca)) or \
                    any(inside(sa, ra, ca, q) for q in surface_points(sb, rb, cb)):
                found.append((na, nb))
    return found


def surface_points(shape, rot, centre, n=12):
    pts = []
    if shape.kind == "sphere":
        r = shape.dims[0]
        for i in range(n + 1):
            th = math.pi * i / n
            for k in range(2 * n):
                ph = math.pi * k / n
                pts.append((r * math.sin(th) * math.cos(ph), r * math.sin(th) * math.sin(ph), r * math.cos(th)))
    elif shape.kind == "cylinder":
        r, h = shape.dims
        for i in range(n + 1):
            z = -h / 2 + h * i / n
            for k in range(2 * n):
                ph = math.pi * k / n
                for rr in ((r,) if 0 < i < n else (r, r / 2, 0.0)):
                    pts.append((rr * math.cos(ph), rr * math.sin(ph), z))
    else:
        hx, hy, hz = (d / 2 for d in shape.dims)
        g = [-1 + 2 * i / n for i in range(n + 1)]
        for u in g:
            for v in g:
                for face in ((hx, u * hy, v * hz), (-hx, u * hy, v * hz), (u * hx, hy, v * hz),
                             (u * hx, -hy, v * hz), (u * hx, v * hy, hz), (u * hx, v * hy, -hz)):
                    pts.append(face)
    return [add(centre, mat_vec(rot, q)) for q in pts]


def inside(shape, rot, centre, point, slack=0.001):
    q = mat_vec(transpose(rot), sub(point, centre))
    if shape.kind == "sphere":
        return norm(q) < shape.dims[0] - slack
    if shape.kind == "cylinder":
        r, h = shape.dims
        return math.hypot(q[0], q[1]) < r - slack and abs(q[2]) < h / 2 - slack
    return all(abs(q[i]) < shape.dims[i] / 2 - slack for i in range(3))


def check_inmoov(p):
    check_structure(p)
    moving = [n for n, j in p.joints.items() if j["type"] != "fixed"]
    if len(moving) <= 50:
        fail(p.path, f"needs more than 50 non-fixed joints, has {len(moving)}")
    for ee in ("r_hand_ee", "l_hand_ee"):
        if ee not in p.links:
            fail(p.path, f"end-effector link {ee} missing")
    frames = p.world_frames()
    overlaps = overlapping_pairs(collision_bodies(p, frames), adjacent_pairs(p))
    if overlaps:
        fail(p.path, "collision shapes overlap in the zero pose: " + ", ".join(f"{a}/{b}" for a, b in overlaps))
    return frames


def check_tree(p, robot_frames):
    check_structure(p)
    frames = p.world_frames(TREE_WORLD_XYZ)
    shoulder = robot_frames["r_shoulder"][1]
    tomatoes = sorted((n for n in p.links if n.startswith("tomato_")), key=lambda n: int(n.split("_")[1]))
    if not 5 <= len(tomatoes) <= 8:
        fail(p.path, f"expected 5-8 tomato links, found {len(tomatoes)}")
    out = []
    for t in tomatoes:
        centre = frames[t][1]
        d = norm(sub(centre, shoulder))
        if d > REACH_LIMIT or centre[0] < MIN_TOMATO_X:
            fail(p.path, f"{t} at {vec(centre)} is not reachable: {d:.3f} m from the right shoulder")
        out.append((t, centre, d))
    overlaps = overlapping_pairs(collision_bodies(p, frames), adjacent_pairs(p))
    if overlaps:
        fail(p.path, "tree parts overlap: " + ", ".join(f"{a}/{b}" for a, b in overlaps))
    # The robot must not start inside the tree.
    for name, (rot, pos) in robot_frames.items():
        del rot
        if pos[0] > TREE_WORLD_XYZ[0] - 0.15:
            fail(p.path, f"robot link {name} is within 0.15 m of the trunk")
    return out


RIGHT_ARM = ("r_omoplate", "r_shoulder_lift", "r_upper_arm_rotate", "r_elbow", "r_wrist_roll",
             "r_wrist_pitch")
# IK start poses (deg, in RIGHT_ARM order): arm forward and bent, with a few wrist variations.
IK_SEEDS = tuple((0, 60, rotate, elbow, roll, 0) for roll in (0, -60, 60) for rotate in (0, 40)
                 for elbow in (60, 100))
PALM_GAP = 0.01
# How much a unit of palm-direction error weighs against a metre of position error in the IK.
APPROACH_WEIGHT = 0.05


def reach(robot, tomato_centre, seed, approach):
    """Right arm joint angles (within limits) that put the palm facing the tomato, PALM_GAP off its
    surface: damped least squares on a point held in front of the palm centre, with a soft wish
    for the palm's normal to point along `approach`."""
    lower = [robot.joints[j]["limits"][0] for j in RIGHT_ARM]
    upper = [robot.joints[j]["limits"][1] for j in RIGHT_ARM]
    q = [math.radians(x) for x in seed]

    def residual(qs):
        rot, pos = robot.frame_of("r_hand_ee", dict(zip(RIGHT_ARM, qs)))
        normal = mat_vec(rot, (0.0, 1.0, 0.0))  # the right palm faces its frame's +y
        point = add(pos, scale(normal, TOMATO_RADIUS + PALM_GAP))
        return list(sub(point, tomato_centre)) + [APPROACH_WEIGHT * x for x in sub(normal, approach)]

    for _ in range(150):
        r = residual(q)
        cols = []
        for i in range(len(q)):
            dq = list(q)
            dq[i] += 1e-6
            cols.append([(a - b) * 1e6 for a, b in zip(residual(dq), r)])
        # dq = J^T (J J^T + lambda^2 I)^-1 (-r)
        n = len(r)
        jjt = [[sum(c[i] * c[k] for c in cols) + (1e-4 if i == k else 0.0) for k in range(n)] for i in range(n)]
        w = solve(jjt, [-x for x in r])
        step = [sum(c[i] * w[i] for i in range(n)) for c in cols]
        q = [min(hi, max(lo, qi + 0.5 * d)) for qi, d, lo, hi in zip(q, step, lower, upper)]
    return q, norm(residual(q)[:3])


def solve(a, b):
    """Gaussian elimination with partial pivoting (small dense systems)."""
    n = len(b)
    m = [list(row) + [rhs] for row, rhs in zip(a, b)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        for r in range(c + 1, n):
            f = m[r][c] / m[c][c]
            m[r] = [x - f * y for x, y in zip(m[r], m[c])]
    x = [0.0] * n
    for r in reversed(range(n)):
        x[r] = (m[r][n] - sum(m[r][k] * x[k] for k in range(r + 1, n))) / m[r][r]
    return x


def arm_links(robot):
    """The right arm's links: everything downstream of r_omoplate."""
    out, frontier = set(), {"r_shoulder_blade"}
    while frontier:
        out |= frontier
        frontier = {j["child"] for j in robot.joints.values() if j["parent"] in frontier}
    return out


def check_reach(robot, tree, tomatoes):
    """Every tomato reachable by the right arm alone (torso still), palm toward it, without the
    arm touching the body or the tree. Returns the arm angles used."""
    tree_bodies = collision_bodies(tree, tree.world_frames(TREE_WORLD_XYZ), "tree/")
    arm = arm_links(robot)
    # Only pairs with exactly one moving arm link can change from the zero pose (checked already).
    skip = adjacent_pairs(robot)
    solutions = []
    for name, centre, _ in tomatoes:
        problems = []
        shoulder = robot.frame_of("r_shoulder", {})[1]
        approaches = (("from the shoulder", scale(sub(centre, shoulder), 1 / norm(sub(centre, shoulder)))),
                      ("from below", (0.0, 0.0, 1.0)))
        for (how, approach), seed in ((a, s) for a in approaches for s in IK_SEEDS):
            q, err = reach(robot, centre, seed, approach)
            if err > 0.005:
                problems.append(f"IK {how} from {seed} misses by {err:.3f} m")
                continue
            bodies = collision_bodies(robot, robot.world_frames(angles=dict(zip(RIGHT_ARM, q))))
            moving = [b for b in bodies if b[0] in arm]
            hits = [(a[0], b[0]) for a in moving for b in [x for x in bodies if x[0] not in arm] + tree_bodies
                    if overlapping_pairs([a, b], skip)]
            if hits:
                problems.append(f"IK {how} from {seed} collides: " + ", ".join(f"{a}/{b}" for a, b in hits))
                continue
            solutions.append((name, how, q))
            break
        else:
            fail(tree.path, f"{name} cannot be reached: " + "; ".join(problems))
    return solutions


def report(robot, frames, tomatoes, solutions):
    moving = [j for j in robot.joints.values() if j["type"] != "fixed"]
    total = sum(l["mass"] for l in robot.links.values())
    print(f"inmoov: {len(robot.links)} links, {len(robot.joints)} joints, {len(moving)} non-fixed")
    print(f"inmoov: total mass {total:.3f} kg, without the pedestal (base_link) "
          f"{total - robot.links['base_link']['mass']:.3f} kg")
    for name in ("r_shoulder", "l_shoulder", "r_hand_ee", "l_hand_ee", "head"):
        print(f"inmoov: {name} at {vec(round(x, 4) for x in frames[name][1])}")
    print(f"tomato_tree: placed at {vec(TREE_WORLD_XYZ)}")
    for name, centre, d in tomatoes:
        print(f"tomato_tree: {name} at {vec(round(x, 4) for x in centre)} "
              f"({d:.3f} m from the right shoulder)")
    for name, how, q in solutions:
        print(f"reach: {name} {how}, right arm at (deg) " + " ".join(f"{math.degrees(x):.0f}" for x in q))


# Effective densities a link may have: hollow printed shells with some servos inside (~150-700
# kg/m^3) up to small nearly solid parts and fruit (~900); nothing denser than solid PLA (1240).
DENSITY_RANGE = (100.0, 1250.0)


def check_densities(model, path):
    for link in model.links:
        density = link.mass / link.shape.volume()
        if not DENSITY_RANGE[0] <= density <= DENSITY_RANGE[1]:
            fail(path, f"link {link.name}: {link.mass} kg in {link.shape.volume():.3g} m^3 is "
                       f"{density:.0f} kg/m^3, outside {DENSITY_RANGE}")


def joint_table(model):
    rows = ["| joint | parent -> child | axis | lower..upper (deg) | effort N*m | meaning |",
            "|---|---|---|---|---|---|"]
    for j in model.joints:
        if j.kind == "fixed":
            continue
        rows.append(f"| `{j.name}` | {j.parent} -> {j.child} | {vec(j.axis)} | "
                    f"{math.degrees(j.lower):.0f}..{math.degrees(j.upper):.0f} | {fmt(j.effort)} | {j.note} |")
    return "\n".join(rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="only check the committed files")
    ap.add_argument("--table", action="store_true", help="print the InMoov joint table (markdown)")
    args = ap.parse_args()
    if args.table:
        print(joint_table(build_inmoov()))
        return
    if not args.check:
        header = "Generated by tools/gen_inmoov.py; edit the generator, not this file."
        for path, model in ((INMOOV_PATH, build_inmoov()), (TREE_PATH, build_tree())):
            check_densities(model, path)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w", encoding="utf-8") as f:
                f.write(to_xml(model, header))
    robot = Parsed(INMOOV_PATH)
    frames = check_inmoov(robot)
    tree = Parsed(TREE_PATH)
    tomatoes = check_tree(tree, frames)
    report(robot, frames, tomatoes, check_reach(robot, tree, tomatoes))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Generates the atlas robot (run: python3 tools/atlas/generate.py [--root REPO_ROOT]).

Writes models/robots/atlas/atlas.xml (MJCF) and models/robots/atlas/profile.yaml.

atlas is the DRC-era Boston Dynamics Atlas (the 2013 "v3" robot of the DARPA Robotics
Challenge trials) with Robotiq 3-finger (S-model) hands and the MultiSense SL head, the
configuration the DRC simulator published as atlas_v3_robotiq_hands. Kinematics (joint
origins, axes, limits) are numbers from the public URDFs of that simulator (osrf/drcsim:
atlas_description/urdf/atlas_v3.urdf, robotiq_hand_description/urdf/robotiq_hand.urdf.xacro,
multisense_sl_description/urdf/multisense_sl.urdf); collision geometry is primitives sized
after the simulator's own simple-shape collision model (atlas_v3_simple_shapes.urdf).
models/README.md tabulates every number against its source and says what was changed:
  - the legs are fixed geometry at their zero configuration (straight) on the harness's
    planar base (slides x, y and a hinge about z) instead of a floating pelvis;
  - the Robotiq hand's two scissor joints (palm_finger_1/2_joint) are fixed at 0 (the
    hand's "basic" mode) and each finger keeps its three phalanx joints; the finger zero is
    the open hand, proximal phalanges splayed 20 degrees outward (the S-model's 155 mm
    aperture); the distal phalanx is 35 mm (the fingertip mesh; it ends in no joint);
  - the head's lidar spindle (hokuyo_joint) is fixed; the head camera sits between the
    stereo pair (the URDF's left/right camera frames at y = +-0.035).
Every body frame is aligned with the world at qpos0, as in the URDF.
Sign conventions (from the URDF axes): back_bky + leans forward, back_bkz + turns left,
back_bkx + rolls right side up; neck_ry + looks down; l_arm_shy - swings the arm forward,
l_arm_shx - lowers the left arm (+ for the right), elx flexes the elbow (+ left, - right),
ely and wry twist the upper arm and forearm, wrx bends the wrist; finger joints + close.
"""
import argparse
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))

# ---------------------------------------------------------------------------------- source
# atlas_v3.urdf joints: parent-frame origin of the child link (xyz), axis, limits [lo, hi].
BACK = [  # pelvis -> ltorso -> mtorso -> utorso
    ("back_bkz", (-0.0125, 0.0, 0.0), (0, 0, 1), (-0.663225, 0.663225)),
    ("back_bky", (0.0, 0.0, 0.16197), (0, 1, 0), (-0.610691, 0.438427)),
    ("back_bkx", (0.0, 0.0, 0.05), (1, 0, 0), (-0.698132, 0.698132)),
]
NECK = ("neck_ry", (0.21672, 0.0, 0.53796), (0, 1, 0), (-0.602139, 1.14494))
ARM = [  # left arm; the right arm mirrors y (and the shy axis' z, elx's range)
    ("shy", (0.06441, 0.13866, 0.10718), (0, 0.5, 0.866025), (-1.5708, 0.785398)),
    ("shx", (0.0, 0.14035, 0.19609), (1, 0, 0), (-1.5708, 1.5708)),
    ("ely", (0.0, 0.187, 0.016), (0, 1, 0), (0.0, 3.14159)),
    ("elx", (0.0, 0.119, 0.00921), (1, 0, 0), (0.0, 2.35619)),
    ("wry", (0.0, 0.187, -0.00921), (0, 1, 0), (0.0, 3.14159)),
    ("wrx", (0.0, 0.119, 0.00921), (1, 0, 0), (-1.1781, 1.1781)),
]
RIGHT_ARM_AXES = {"shy": (0, 0.5, -0.866025), "elx": (1, 0, 0)}
RIGHT_ARM_RANGES = {"elx": (-2.35619, 0.0)}
# Leg frames at zero (pelvis -> uglut -> lglut -> uleg -> lleg -> talus), left side.
HIP = (0.0, 0.089, 0.0)
ULEG = (0.05, 0.0, -0.05)
LLEG = (-0.05, 0.0, -0.374)
TALUS = (0.0, 0.0, -0.422)
FOOT_BOX = ((0.048, 0.0, -0.056119), (0.26, 0.124887, 0.05))  # centre in talus, full size
# atlas_v3_robotiq_hands: the Robotiq palm frame in l_hand/r_hand (left: rpy pi pi pi, the
# identity; right: rpy pi 0 0).
HAND_MOUNT = (-0.00125, 0.17, 0.01)
# robotiq_hand.urdf.xacro: finger bases in the palm frame (x across the palm, y out of it,
# z along the palm), link_0 -> joint_1 (20 mm, the S-model's finger macro), phalanx lengths
# link_1 -> joint_2 (57.15 mm), link_2 -> joint_3 (39 mm), and the joint limits.
FINGER_BASES = {"1": (-0.0455, 0.0214, 0.036), "2": (-0.0455, 0.0214, -0.036),
                "middle": (0.0455, 0.0214, 0.0)}
LINK0 = 0.020
PHALANX = (0.05715, 0.039, 0.035)
FINGER_RANGES = ((0.0, 1.2217), (0.0, 1.5708), (-0.6632, 1.0471))
OPEN_SPLAY = math.radians(20.0)
PHALANX_R = 0.011
# multisense_sl.urdf: head collision boxes (centre, full size) and the lidar housing.
HEAD_BOXES = [((-0.0503, 0.0, -0.00195), (0.1311, 0.12, 0.0591)),
              ((-0.093, 0.0, 0.0868), (0.0468, 0.12, 0.1184))]
LIDAR = (-0.0446, 0.0, 0.0880)  # hokuyo_joint origin in the head
HEAD_CAM = (0.02, 0.0, -0.002)  # between the stereo cameras (y +-0.035, z -0.002), at the lens
# Horizontal field of view 80 degrees (the MultiSense SL's 80 x 45 degree imager); the
# harness's head sensor is 4:3, so fovy = 2 atan(tan(40 deg) * 3 / 4).
CAM_FOVY = math.degrees(2 * math.atan(math.tan(math.radians(40.0)) * 0.75))

FOOT_CLEARANCE = 0.005
PELVIS_Z = -(HIP[2] + ULEG[2] + LLEG[2] + TALUS[2] + FOOT_BOX[0][2] - FOOT_BOX[1][2] / 2) \
    + FOOT_CLEARANCE
# The grasp centre (palm site) in the Robotiq palm frame: 85 mm out of the palm, so that an
# object 1.5 to 2.8 cm further out (reach's stand-offs) sits between the phalanx joints.
PALM_SITE = (0.0, 0.085, 0.0)

SPEED_LIMITS = {  # chain: (velocity, acceleration); the URDF's 12 rad/s is no servo rate
    "base": (0.4, 0.8), "torso": (0.5, 1.5), "head": (1.2, 4.0),
    "left_arm": (1.0, 2.5), "right_arm": (1.0, 2.5),
    "left_hand": (1.5, 6.0), "right_hand": (1.5, 6.0)}

# ------------------------------------------------------------------------------- postures
FIST = [1.2, 0.8, 0.3]  # per finger, off the limits; the fingers interleave without touching
REST_LEFT_ARM = [0.0, -1.5, 1.5708, 0.05, 1.5708, 0.0]  # hanging, close to the body
WAVE_RIGHT_ARM = lambda elx: [0.0, 0.0, 0.0, elx, 1.5708, 0.0]
ARM_MIRROR = [1, -1, 1, -1, 1, -1]  # the right arm's value of a mirrored left posture


def mirror_arm(values):
    return [s * v for s, v in zip(ARM_MIRROR, values)]


POSTURES = {
    "rest": {
        "torso": [0.0, 0.0, 0.0],
        "head": [0.9],  # looking 52 degrees down, at the work surface in front
        "left_arm": REST_LEFT_ARM,
        "right_arm": mirror_arm(REST_LEFT_ARM),
        "left_hand": [0.0] * 9,
        "right_hand": [0.0] * 9,
    },
    "fist": {"left_hand": FIST * 3, "right_hand": FIST * 3},
    # Right upper arm out to the side, forearm up, fingers up.
    "wave_start": {"right_arm": WAVE_RIGHT_ARM(-1.55)},
    "bow": {"torso": [0.0, 0.4, 0.0], "head": [0.3]},
}
CANNED = {
    # Forearm swings side to side about the elbow from wave_start, three times.
    "wave": (["right_arm"], [[0.0] + WAVE_RIGHT_ARM(-1.55), [0.5] + WAVE_RIGHT_ARM(-1.2),
                             [1.25] + WAVE_RIGHT_ARM(-1.9), [2.0] + WAVE_RIGHT_ARM(-1.2),
                             [2.75] + WAVE_RIGHT_ARM(-1.9), [3.25] + WAVE_RIGHT_ARM(-1.55)]),
    # Lean forward at the back and nod, hold, come back.
    "bow": (["torso", "head"], [[0.0, 0.0, 0.0, 0.0, 0.9], [1.0, 0.0, 0.4, 0.0, 0.3],
                                [2.0, 0.0, 0.4, 0.0, 0.3], [3.0, 0.0, 0.0, 0.0, 0.9]]),
}


# --------------------------------------------------------------------------------- helpers
def fmt(x):
    x = float(x)
    if abs(x) < 5e-7:
        return "0"
    s = "%.6f" % x
    s = s.rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def vec(v):
    return " ".join(fmt(x) for x in v)


def add(a, b, s=1.0):
    return tuple(a[i] + s * b[i] for i in range(3))


def scale(a, s):
    return tuple(x * s for x in a)


def mirror_y(v):
    return (v[0], -v[1], v[2])


class Writer:
    def __init__(self):
        self.lines, self.depth, self.actuators = [], 0, []

    def w(self, s):
        self.lines.append("  " * self.depth + s)

    def open(self, s):
        self.w(s)
        self.depth += 1

    def close(self, s):
        self.depth -= 1
        self.w(s)

    def joint(self, name, cls, axis, rng, slide=False):
        t = ' type="slide"' if slide else ""
        self.w('<joint name="%s" class="%s"%s axis="%s" range="%s %s"/>'
               % (name, cls, t, vec(axis), fmt(rng[0]), fmt(rng[1])))
        self.actuators.append((name, cls, rng))

    def capsule(self, name, a, b, r, cls=None):
        c = ' class="%s"' % cls if cls else ""
        self.w('<geom name="%s"%s fromto="%s" size="%s"/>' % (name, c, vec(a + b), fmt(r)))

    def cylinder(self, name, a, b, r, cls=None):
        c = ' class="%s"' % cls if cls else ""
        self.w('<geom name="%s"%s type="cylinder" fromto="%s" size="%s"/>'
               % (name, c, vec(a + b), fmt(r)))

    def sphere(self, name, p, r, cls=None):
        c = ' class="%s"' % cls if cls else ""
        self.w('<geom name="%s"%s type="sphere" pos="%s" size="%s"/>' % (name, c, vec(p), fmt(r)))

    def box(self, name, p, full, cls=None):
        c = ' class="%s"' % cls if cls else ""
        self.w('<geom name="%s"%s type="box" pos="%s" size="%s"/>'
               % (name, c, vec(p), vec(scale(full, 0.5))))


# ------------------------------------------------------------------------------------ model
def write_defaults(x):
    x.open("<default>")
    x.open('<default class="atlas">')
    x.w('<geom type="capsule" density="1000" rgba="0.72 0.74 0.77 1" friction="1 0.01 0.001"/>')
    x.w('<joint damping="10" armature="0.05"/>')
    x.w('<position kp="400"/>')
    x.w('<site group="4" rgba="1 0.3 0.3 0.6"/>')
    for cls, rgba in (("at_dark", "0.16 0.17 0.19 1"), ("at_blue", "0.16 0.33 0.62 1"),
                      ("at_hand", "0.22 0.23 0.25 1")):
        x.open('<default class="%s">' % cls)
        x.w('<geom rgba="%s"/>' % rgba)
        x.close("</default>")
    x.open('<default class="at_visual">')
    x.w('<geom contype="0" conaffinity="0" density="0" rgba="0.85 0.45 0.1 1"/>')
    x.close("</default>")
    for cls, damping, armature, kp in (("at_base", 600, 1, 2000), ("at_back", 200, 0.5, 3000),
                                       ("at_neck", 8, 0.05, 200), ("at_shoulder", 30, 0.1, 600),
                                       ("at_elbow", 15, 0.05, 400), ("at_wrist", 5, 0.03, 200)):
        x.open('<default class="%s">' % cls)
        x.w('<joint damping="%s" armature="%s"/>' % (fmt(damping), fmt(armature)))
        x.w('<position kp="%s"/>' % fmt(kp))
        x.close("</default>")
    x.open('<default class="at_finger">')
    x.w('<joint damping="0.5" armature="0.005"/>')
    x.w('<position kp="30"/>')
    x.w('<geom rgba="0.12 0.12 0.13 1" friction="1.5 0.02 0.002"/>')
    x.close("</default>")
    x.close("</default>")
    x.close("</default>")


def write_legs(x):
    for s, sy in (("l", 1), ("r", -1)):
        hip = (HIP[0], sy * HIP[1], HIP[2])
        uleg = add(hip, ULEG)
        lleg = add(uleg, LLEG)
        talus = add(lleg, TALUS)
        x.sphere("%s_hip" % s, add(uleg, (-0.02, 0.0, -0.05)), 0.075, "at_dark")
        x.capsule("%s_thigh" % s, add(uleg, (-0.02, sy * 0.01, -0.12)),
                  add(uleg, (-0.045, sy * 0.005, -0.31)), 0.07)
        x.sphere("%s_knee" % s, lleg, 0.062, "at_dark")
        x.capsule("%s_shin" % s, add(lleg, (0.012, 0.0, -0.07)), add(lleg, (0.03, 0.0, -0.33)),
                  0.058)
        x.sphere("%s_ankle" % s, talus, 0.035, "at_dark")
        x.box("%s_foot" % s, add(talus, FOOT_BOX[0]), FOOT_BOX[1], "at_dark")


def write_torso_geoms(x):
    # utorso: the simple-shape model's chest, backpack and roll cage.
    x.box("chest", (-0.048395, 0.0, 0.20), (0.530175, 0.25, 0.34))
    x.box("shoulders", (0.05, 0.0, 0.45), (0.4, 0.3, 0.18))
    x.box("backpack", (-0.2, 0.0, 0.46), (0.266306, 0.381719, 0.18), "at_blue")
    x.box("backpack_top", (-0.2, 0.0, 0.58), (0.266306, 0.223, 0.091), "at_blue")
    # The roll cage over the head: the simple-shape model's two cross bars, joined to the
    # shoulders by side rails and posts.
    x.capsule("cage_front", (0.15, -0.06, 0.724), (0.15, 0.06, 0.724), 0.008, "at_dark")
    x.capsule("cage_top", (-0.002, -0.065, 0.71), (-0.002, 0.065, 0.71), 0.008, "at_dark")
    for s, sy in (("l", 1), ("r", -1)):
        x.capsule("%s_cage_rail" % s, (-0.002, sy * 0.065, 0.71), (0.15, sy * 0.06, 0.724), 0.008,
                  "at_dark")
        x.capsule("%s_cage_front" % s, (0.15, sy * 0.06, 0.724), (0.2, sy * 0.13, 0.545), 0.008,
                  "at_dark")
        x.capsule("%s_cage_rear" % s, (-0.002, sy * 0.065, 0.71), (-0.06, sy * 0.13, 0.555), 0.008,
                  "at_dark")


def write_head(x):
    x.open('<body name="head" pos="%s">' % vec(NECK[1]))
    x.joint(NECK[0], "at_neck", NECK[2], NECK[3])
    for i, (c, full) in enumerate(HEAD_BOXES):
        x.box("head_%d" % i, c, full, "at_dark")
    x.box("lidar_base", add(LIDAR, (0.01885, 0.0, -0.02119)), (0.08, 0.06, 0.04238), "at_dark")
    x.cylinder("lidar", add(LIDAR, (0.03, 0.0, 0.0)), add(LIDAR, (0.03, 0.0, 0.047)), 0.024425,
               "at_dark")
    for s, sy in (("l", 1), ("r", -1)):
        x.w('<geom name="%s_lens" class="at_visual" type="cylinder" fromto="%s" size="0.012"/>'
            % (s, vec((0.012, sy * 0.035, -0.002, 0.017, sy * 0.035, -0.002))))
    x.w('<camera name="head_cam" pos="%s" xyaxes="0 -1 0 0 0 1" fovy="%s"/>'
        % (vec(HEAD_CAM), fmt(CAM_FOVY)))
    x.close("</body>")


def palm_to_body(p, s):
    """A point or axis of the Robotiq palm frame in the hand body: left identity, right
    rotated pi about x."""
    return tuple(p) if s == "l" else (p[0], -p[1], -p[2])


def write_hand(x, s):
    mount = HAND_MOUNT if s == "l" else mirror_y(HAND_MOUNT)
    P = lambda p: add(mount, palm_to_body(p, s))  # palm-frame point -> hand body
    A = lambda a: palm_to_body(a, s)  # palm-frame axis -> hand body
    # The wrist's mounting flange (l_hand's simple shapes) and the Robotiq palm.
    x.capsule("%s_wrist_mount" % s, P((0, -0.15, 0)), P((0, -0.06, 0)), 0.04, "at_dark")
    # The palm spans the finger bases: +-(45.5 + 15) mm across, +-(36 + 15) mm along.
    x.box("%s_palm" % s, P((0.0, -0.005, 0.0)), (0.124, 0.07, 0.104), "at_hand")
    sx, sy_, sz = palm_to_body((1, 0, 0), s), palm_to_body((0, 1, 0), s), None
    del sz
    # Palm site: +x out of the palm along the fingers (approach), +y across the palm towards
    # the middle finger (closing), origin at the grasp centre.
    x.w('<site name="%s_palm" pos="%s" xyaxes="%s" size="0.012"/>'
        % (s, vec(P(PALM_SITE)), vec(sy_ + sx)))
    for f, base in FINGER_BASES.items():
        out = -1.0 if base[0] < 0 else 1.0  # the finger's outward side along palm x
        joint_at = (base[0], base[1] + LINK0, base[2])
        x.box("%s_finger_%s_link_0" % (s, f), P((base[0], base[1] + LINK0 / 2 - 0.002, base[2])),
              (0.03, LINK0 + 0.004, 0.03), "at_hand")
        d = (out * math.sin(OPEN_SPLAY), math.cos(OPEN_SPLAY), 0.0)  # open phalanx direction
        axis = A((0.0, 0.0, out))  # closing turns the phalanx towards the palm's middle
        x.open('<body name="%s_finger_%s_link_1" pos="%s">' % (s, f, vec(P(joint_at))))
        pos = (0.0, 0.0, 0.0)
        for k in range(3):
            if k > 0:
                x.open('<body name="%s_finger_%s_link_%d" pos="%s">'
                       % (s, f, k + 1, vec(A(scale(d, PHALANX[k - 1])))))
            x.joint("%s_finger_%s_joint_%d" % (s, f, k + 1), "at_finger", axis, FINGER_RANGES[k])
            start = 0.004 if k == 0 else 0.0
            end = PHALANX[k] - (PHALANX_R if k == 2 else 0.004)
            x.capsule("%s_finger_%s_link_%d" % (s, f, k + 1), A(scale(d, start)),
                      A(scale(d, end)), PHALANX_R, "at_finger")
        del pos
        for _ in range(3):
            x.close("</body>")


def write_arm(x, s):
    sy = 1 if s == "l" else -1
    names = []
    depth0 = x.depth
    for i, (j, origin, axis, rng) in enumerate(ARM):
        if s == "r":
            origin = mirror_y(origin)
            axis = RIGHT_ARM_AXES.get(j, axis)
            rng = RIGHT_ARM_RANGES.get(j, rng)
        body = ["clav", "scap", "uarm", "larm", "farm", "hand"][i]
        cls = "at_shoulder" if j in ("shy", "shx", "ely") else "at_elbow" if j == "elx" \
            else "at_wrist"
        x.open('<body name="%s_%s" pos="%s">' % (s, body, vec(origin)))
        x.joint("%s_arm_%s" % (s, j), cls, axis, rng)
        names.append("%s_arm_%s" % (s, j))
        Y = lambda v: (v[0], sy * v[1], v[2])
        if body == "clav":
            x.capsule("%s_clav" % s, Y((-0.01, 0.035, 0.07)), Y((0.0, 0.12, 0.19)), 0.045)
        elif body == "scap":
            x.cylinder("%s_shoulder" % s, Y((-0.07, 0.0, 0.0)), Y((0.07, 0.0, 0.0)), 0.05, "at_dark")
            x.capsule("%s_scap" % s, Y((0.0, 0.06, 0.012)), Y((0.0, 0.16, 0.015)), 0.052)
        elif body == "uarm":
            x.capsule("%s_uarm" % s, Y((0.0, 0.01, 0.0)), Y((0.0, 0.07, 0.005)), 0.05)
            x.cylinder("%s_elbow" % s, Y((-0.06, 0.119, 0.00921)), Y((0.06, 0.119, 0.00921)),
                       0.045, "at_dark")
        elif body == "larm":
            x.capsule("%s_larm" % s, Y((0.0, 0.055, 0.0)), Y((0.0, 0.17, -0.005)), 0.05, "at_blue")
        elif body == "farm":
            x.capsule("%s_farm" % s, Y((0.0, 0.01, 0.0)), Y((0.0, 0.075, 0.005)), 0.047)
            x.cylinder("%s_wrist" % s, Y((-0.05, 0.119, 0.00921)), Y((0.05, 0.119, 0.00921)),
                       0.042, "at_dark")
        elif body == "hand":
            write_hand(x, s)
    while x.depth > depth0:
        x.close("</body>")
    return names


def build_model():
    x = Writer()
    x.w('<mujoco model="atlas">')
    x.depth = 1
    x.w("<!-- Generated by tools/atlas/generate.py; do not edit by hand. The DRC-era Atlas (v3)")
    x.w("     with Robotiq 3-finger hands and the MultiSense SL head, kinematics from the DRC")
    x.w("     simulator's URDFs (models/README.md lists every number against its source).")
    x.w("     Planar base (x, y, yaw), fixed straight legs, 3-DOF back (bkz, bky, bkx), 1-DOF")
    x.w("     neck (pitch), two 6-DOF arms (shy, shx, ely, elx, wry, wrx), three fingers of")
    x.w("     three phalanges per hand. Every body frame is world-aligned at qpos0. Palm sites:")
    x.w("     +x out of the palm along the fingers, +y towards the middle finger (closing),")
    x.w("     origin at the grasp centre. -->")
    x.w('<compiler angle="radian" autolimits="true"/>')
    x.w('<option timestep="0.002"/>')
    write_defaults(x)
    x.open("<worldbody>")
    x.open('<body name="pelvis" childclass="atlas" pos="0 0 %s">' % fmt(PELVIS_Z))
    x.joint("pelvis_x", "at_base", (1, 0, 0), (-5, 5), slide=True)
    x.joint("pelvis_y", "at_base", (0, 1, 0), (-5, 5), slide=True)
    x.joint("pelvis_yaw", "at_base", (0, 0, 1), (-3.14159, 3.14159))
    x.capsule("pelvis", (0.01, -0.08, 0.03), (0.01, 0.08, 0.03), 0.1, "at_dark")
    x.box("pelvis_back", (-0.1, 0.0, -0.05), (0.1, 0.15, 0.2), "at_dark")
    write_legs(x)
    bodies = ["ltorso", "mtorso", "utorso"]
    for (name, origin, axis, rng), body in zip(BACK, bodies):
        x.open('<body name="%s" pos="%s">' % (body, vec(origin)))
        x.joint(name, "at_back", axis, rng)
        if body == "ltorso":  # no geometry of its own: atlas_v3.urdf's inertial
            x.w('<inertial pos="-0.0112984 0 0.0746835" mass="2.27" '
                'diaginertia="0.0039092 0.00341694 0.00174492"/>')
        if body == "mtorso":
            x.sphere("waist", (0.0, 0.0, 0.05), 0.06, "at_dark")
    write_torso_geoms(x)
    write_head(x)
    arms = {s: write_arm(x, s) for s in ("l", "r")}
    for _ in bodies:
        x.close("</body>")
    x.close("</body>")  # pelvis
    x.close("</worldbody>")
    x.open("<actuator>")
    for name, cls, rng in x.actuators:
        x.w('<position name="%s" class="%s" joint="%s" ctrlrange="%s %s"/>'
            % (name, cls, name, fmt(rng[0]), fmt(rng[1])))
    x.close("</actuator>")
    x.depth = 0
    x.w("</mujoco>")
    return "\n".join(x.lines) + "\n", arms


# ---------------------------------------------------------------------------------- profile
def ylist(values):
    return "[" + ", ".join(fmt(v) for v in values) + "]"


def names(items):
    return "[" + ", ".join(items) + "]"


def finger_joints(s):
    return {f: ["%s_finger_%s_joint_%d" % (s, f, k) for k in (1, 2, 3)] for f in FINGER_BASES}


def write_profile(path, arms, height):
    ranges = {}
    for j, _, _, rng in ARM:
        ranges["l_arm_" + j] = rng
        ranges["r_arm_" + j] = RIGHT_ARM_RANGES.get(j, rng)
    chains = {
        "base": ["pelvis_x", "pelvis_y", "pelvis_yaw"],
        "torso": [j for j, _, _, _ in BACK],
        "head": [NECK[0]],
        "left_arm": arms["l"],
        "right_arm": arms["r"],
        "left_hand": sum(finger_joints("l").values(), []),
        "right_hand": sum(finger_joints("r").values(), []),
    }
    for j, (lo, hi) in [(b[0], b[3]) for b in BACK] + [(NECK[0], NECK[3])]:
        ranges[j] = (lo, hi)
    for s in ("l", "r"):
        for joints in finger_joints(s).values():
            for j, rng in zip(joints, FINGER_RANGES):
                ranges[j] = rng
    for pname, posture in POSTURES.items():  # every value within its joint's range
        for chain, values in posture.items():
            assert len(values) == len(chains[chain]), (pname, chain)
            for j, v in zip(chains[chain], values):
                lo, hi = ranges[j]
                assert lo <= v <= hi, (pname, j, v)
    o = ["# Generated by tools/atlas/generate.py; do not edit by hand.",
         "name: atlas",
         "model: atlas.xml",
         "description: >-",
         "  The DRC-era Boston Dynamics Atlas (v3, 2013) with Robotiq 3-finger hands and the",
         "  MultiSense SL head, kinematics from the DRC simulator's public URDFs (1.88 m; planar",
         "  base, fixed legs, 3-DOF back, 1-DOF neck pitch, two 6-DOF arms, three fingers of",
         "  three phalanges).",
         "height_m: %s                 # top of the roll cage at rest" % fmt(round(height, 3)),
         "chains:"]
    for c, js in chains.items():
        ee = ", end_effector: %s_palm" % c[0] if c.endswith("_arm") else ""
        o.append("  %-11s {joints: %s%s}" % (c + ":", names(js), ee))
    o.append("speed_limits:                # per chain: joint velocity (rad/s, m/s) and acceleration")
    for c, (v, a) in SPEED_LIMITS.items():
        o.append("  %-11s {velocity: %s, acceleration: %s}" % (c + ":", fmt(v), fmt(a)))
    o.append("head_camera: head_cam")
    o.append("hands:")
    for side, s in (("left", "l"), ("right", "r")):
        o.append("  %s:" % side)
        o.append("    palm: %s_palm" % s)
        o.append("    approach: [1, 0, 0]        # out of the palm, along the fingers")
        o.append("    closing: [0, 1, 0]         # the middle finger against fingers 1 and 2")
        o.append("    fingers:")
        for f, js in finger_joints(s).items():
            o.append("      - {joints: %s," % names(js))
            o.append("         bodies: %s}"
                     % names(["%s_finger_%s_link_%d" % (s, f, k) for k in (1, 2, 3)]))
    o.append("postures:")
    o.append("  # arms: [shy, shx, ely, elx, wry, wrx]; hands: fingers 1, 2, middle x joints 1..3")
    for pname, posture in POSTURES.items():
        o.append("  %s:" % pname)
        for c, values in posture.items():
            o.append("    %-11s %s" % (c + ":", ylist(values)))
    o.append("mirror_signs:                # the other side's value of a mirrored joint")
    o.append("  arm:        %s" % ylist(ARM_MIRROR))
    o.append("  hand:       %s" % ylist([1] * 9))
    o.append("canned:                      # keyframes: [time_s, joint values...]")
    for name, (cs, frames) in CANNED.items():
        o.append("  %s:" % name)
        o.append("    chains: %s" % names(cs))
        o.append("    keyframes:")
        for frame in frames:
            o.append("      - %s" % ylist(frame))
    with open(path, "w") as f:
        f.write("\n".join(o) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", default=os.path.normpath(os.path.join(HERE, "..", "..")))
    args = ap.parse_args()
    robot_dir = os.path.join(args.root, "models", "robots", "atlas")
    os.makedirs(robot_dir, exist_ok=True)
    text, arms = build_model()
    with open(os.path.join(robot_dir, "atlas.xml"), "w") as f:
        f.write(text)
    utorso_z = PELVIS_Z + sum(b[1][2] for b in BACK)
    height = utorso_z + 0.724 + 0.008  # the roll cage's front bar
    write_profile(os.path.join(robot_dir, "profile.yaml"), arms, height)
    print("wrote atlas.xml and profile.yaml under %s (pelvis at %.4f m, height %.3f m)"
          % (robot_dir, PELVIS_Z, height))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Generates the minibot robot from one kinematic table (standard library only).

Writes, relative to the repository root:
  models/robots/minibot/minibot.urdf        URDF (urdfdom + MuJoCo URDF importer)
  models/robots/minibot/minibot.xml         the MJCF twin: same bodies, joints, frames,
                                            inertials and collision primitives
  models/robots/minibot/profile.yaml        profile of the MJCF variant
  models/robots/minibot_urdf/profile.yaml   profile of the URDF variant

Both model files are emitted from the LINKS table below, so joint names, types, axes,
limits, link frames (joint origins), inertials and geoms agree exactly. Every link frame is
axis-aligned with its parent except the fixed palm frames (LPalm/RPalm), whose +x points
along the fingers.

Usage: python3 tools/minibot/generate.py [--root REPO_ROOT]
"""

import argparse
import math
import os

HALF_PI = math.pi / 2.0

# ----------------------------------------------------------------------------------------
# Colours (white/orange plastic look).
WHITE = (0.93, 0.93, 0.91, 1.0)
ORANGE = (0.95, 0.47, 0.12, 1.0)
GREY = (0.25, 0.26, 0.28, 1.0)
COLOURS = {"white": WHITE, "orange": ORANGE, "grey": GREY}

# ----------------------------------------------------------------------------------------
# Key dimensions (metres).
PELVIS_Z = 0.55           # BaseYaw joint origin = Pelvis frame height above the floor
TORSO_JOINT_Z = 0.05      # TorsoPitch origin in the Pelvis frame
HEAD_JOINT_Z = 0.32       # HeadYaw origin in the Torso frame
HEAD_CENTRE_Z = 0.10      # head sphere centre in the Head frame
HEAD_RADIUS = 0.085
SHOULDER_Y = 0.16         # shoulder joints in the Torso frame
SHOULDER_Z = 0.235
UPPER_ARM = 0.20          # shoulder -> elbow
FOREARM = 0.19            # elbow -> wrist
PALM_OFFSET = 0.085       # wrist joint -> palm frame origin (grasp centre)
FINGER_BASE_X = -0.03     # finger proximal joints in the palm frame
FINGER_BASE_Y = 0.048
PROX_LEN = 0.045
DIST_LEN = 0.036

# Head camera: in front of the face (just outside the head sphere), looking along the
# head's +x, pitched down by 30 degrees: image up = (sin 30, 0, cos 30) in the Head frame.
CAM_POS = (0.09, 0.0, 0.10)
CAM_XYAXES = (0.0, -1.0, 0.0, 0.5, 0.0, math.sqrt(3.0) / 2.0)
CAM_FOVY = 60

# Actuator gains per chain (MJCF <position kp>; the same numbers go to the URDF profile's
# actuator_kp so that both variants get identical servos).
SPEED_LIMITS = {  # chain: (max joint velocity, max joint acceleration)
    "base": (0.4, 0.8),
    "torso": (0.8, 2.0),
    "head": (1.5, 4.0),
    "left_arm": (1.2, 3.0),
    "right_arm": (1.2, 3.0),
    "left_hand": (2.0, 8.0),
    "right_hand": (2.0, 8.0),
}
KP = {"base": 1000, "torso": 800, "head": 300, "left_arm": 500, "right_arm": 500,
      "left_hand": 30, "right_hand": 30}


# ----------------------------------------------------------------------------------------
# The kinematic table.
class Geom:
    def __init__(self, name, kind, size, pos=(0, 0, 0), colour="white"):
        # kind: box (half extents), cylinder (radius, half length, along local z), sphere (r)
        self.name, self.kind, self.size, self.pos, self.colour = name, kind, size, pos, colour


class Link:
    def __init__(self, name, parent, joint, jtype, xyz, axis=None, rng=None, rpy=(0, 0, 0),
                 chain=None, effort=50.0, velocity=2.0, damping=0.0, mass=0.1,
                 inertia_box=(0.02, 0.02, 0.02), com=(0, 0, 0), geoms=()):
        self.name, self.parent, self.joint, self.jtype = name, parent, joint, jtype
        self.xyz, self.axis, self.rng, self.rpy = xyz, axis, rng, rpy
        self.chain, self.effort, self.velocity, self.damping = chain, effort, velocity, damping
        self.mass, self.com, self.geoms = mass, com, list(geoms)
        a, b, c = inertia_box  # half extents of the box whose inertia the link gets
        self.inertia = tuple(float("%.6g" % (mass / 3.0 * (u * u + v * v)))
                             for u, v in ((b, c), (a, c), (a, b)))


def build_links():
    L = []
    # Planar base: BaseRoot (fixed to the world) > BaseX > BaseY > BaseYaw.
    L.append(Link("BaseRoot", None, None, None, None, mass=0.01,
                  inertia_box=(0.01, 0.01, 0.01)))
    L.append(Link("BaseXLink", "BaseRoot", "BaseX", "prismatic", (0, 0, 0), (1, 0, 0),
                  (-5.0, 5.0), chain="base", effort=2000, velocity=1.0, damping=300,
                  mass=0.5, inertia_box=(0.05, 0.05, 0.05)))
    L.append(Link("BaseYLink", "BaseXLink", "BaseY", "prismatic", (0, 0, 0), (0, 1, 0),
                  (-5.0, 5.0), chain="base", effort=2000, velocity=1.0, damping=300,
                  mass=0.5, inertia_box=(0.05, 0.05, 0.05)))
    # Pelvis with the fixed legs (no leg joints). Leg geoms in the Pelvis frame (z=0.55).
    legs = [Geom("PelvisBox", "box", (0.065, 0.10, 0.05), (0, 0, 0), "white")]
    for side, s in (("L", 1), ("R", -1)):
        y = s * 0.065
        legs += [
            Geom(side + "Thigh", "cylinder", (0.045, 0.12), (0, y, -0.15), "white"),
            Geom(side + "Knee", "sphere", (0.043,), (0, y, -0.27), "orange"),
            Geom(side + "Shin", "cylinder", (0.038, 0.12), (0, y, -0.38), "white"),
            Geom(side + "Foot", "box", (0.085, 0.045, 0.02), (0.025, y, -0.52), "grey"),
        ]
    L.append(Link("Pelvis", "BaseYLink", "BaseYaw", "revolute", (0, 0, PELVIS_Z), (0, 0, 1),
                  (-3.14159, 3.14159), chain="base", effort=500, velocity=2.0, damping=100,
                  mass=8.0, com=(0, 0, -0.15), inertia_box=(0.08, 0.11, 0.27), geoms=legs))
    L.append(Link("Torso", "Pelvis", "TorsoPitch", "revolute", (0, 0, TORSO_JOINT_Z),
                  (0, 1, 0), (-0.2, 0.6), chain="torso", effort=200, velocity=1.5,
                  damping=50, mass=6.0, com=(0, 0, 0.15), inertia_box=(0.07, 0.11, 0.14),
                  geoms=[Geom("TorsoWaist", "cylinder", (0.06, 0.03), (0, 0, 0.03), "grey"),
                         Geom("TorsoChest", "box", (0.07, 0.11, 0.115), (0, 0, 0.165),
                              "white")]))
    L.append(Link("Head", "Torso", "HeadYaw", "revolute", (0, 0, HEAD_JOINT_Z), (0, 0, 1),
                  (-2.0, 2.0), chain="head", effort=20, velocity=3.0, damping=5,
                  mass=1.5, com=(0, 0, HEAD_CENTRE_Z),
                  inertia_box=(HEAD_RADIUS, HEAD_RADIUS, HEAD_RADIUS),
                  geoms=[Geom("HeadNeck", "cylinder", (0.03, 0.02), (0, 0, 0.01), "grey"),
                         Geom("HeadSkull", "sphere", (HEAD_RADIUS,), (0, 0, HEAD_CENTRE_Z),
                              "white")]))
    for side, s in (("L", 1), ("R", -1)):
        arm = "left_arm" if s > 0 else "right_arm"
        hand = "left_hand" if s > 0 else "right_hand"

        def mirrored(lo, hi):  # range of a joint about x or z on the right side
            return (lo, hi) if s > 0 else (-hi, -lo)

        L.append(Link(side + "Shoulder", "Torso", side + "ShoulderPitch", "revolute",
                      (0, s * SHOULDER_Y, SHOULDER_Z), (0, 1, 0), (-3.0, 1.0), chain=arm,
                      effort=40, velocity=3.0, damping=10, mass=0.3,
                      inertia_box=(0.045, 0.045, 0.045),
                      geoms=[Geom(side + "ShoulderBall", "sphere", (0.045,), (0, 0, 0),
                                  "orange")]))
        L.append(Link(side + "Biceps", side + "Shoulder", side + "ShoulderRoll", "revolute",
                      (0, 0, 0), (1, 0, 0), mirrored(-0.3, 1.6), chain=arm, effort=40,
                      velocity=3.0, damping=10, mass=0.6, com=(0, 0, -0.09),
                      inertia_box=(0.034, 0.034, 0.09),
                      geoms=[Geom(side + "UpperArm", "cylinder", (0.034, 0.0675),
                                  (0, 0, -0.0875), "white")]))
        L.append(Link(side + "Elbow", side + "Biceps", side + "ElbowYaw", "revolute",
                      (0, 0, -UPPER_ARM), (0, 0, 1), mirrored(-2.0, 2.0), chain=arm,
                      effort=20, velocity=3.0, damping=5, mass=0.2,
                      inertia_box=(0.036, 0.036, 0.036),
                      geoms=[Geom(side + "ElbowBall", "sphere", (0.036,), (0, 0, 0),
                                  "orange")]))
        L.append(Link(side + "ForeArm", side + "Elbow", side + "ElbowRoll", "revolute",
                      (0, 0, 0), (0, 1, 0), (-2.1, 0.0), chain=arm, effort=20,
                      velocity=3.0, damping=5, mass=0.5, com=(0, 0, -0.11),
                      inertia_box=(0.03, 0.03, 0.08),
                      geoms=[Geom(side + "ForeArmTube", "cylinder", (0.03, 0.07),
                                  (0, 0, -0.11), "white")]))
        L.append(Link(side + "Wrist", side + "ForeArm", side + "WristYaw", "revolute",
                      (0, 0, -FOREARM), (0, 0, 1), mirrored(-1.8, 1.8), chain=arm,
                      effort=10, velocity=4.0, damping=2, mass=0.15, com=(0, 0, -0.012),
                      inertia_box=(0.026, 0.026, 0.012),
                      geoms=[Geom(side + "WristRing", "cylinder", (0.026, 0.012),
                                  (0, 0, -0.012), "orange")]))
        # Palm frame: +x along the fingers (down at q=0), +y the opening direction of the
        # gripper (forward for the left hand, backward for the right), +z the palm normal
        # pointing to the body midline at q=0.
        palm_rpy = (HALF_PI, HALF_PI, 0.0) if s > 0 else (-HALF_PI, HALF_PI, 0.0)
        L.append(Link(side + "Palm", side + "Wrist", side + "PalmFixed", "fixed",
                      (0, 0, -PALM_OFFSET), rpy=palm_rpy, mass=0.25, com=(-0.05, 0, 0),
                      inertia_box=(0.022, 0.062, 0.016),
                      geoms=[Geom(side + "PalmBlock", "box", (0.022, 0.062, 0.016),
                                  (-0.05, 0, 0), "white")]))
        for f, fy, az in (("1", FINGER_BASE_Y, -1), ("2", -FINGER_BASE_Y, 1)):
            prox, dist = side + "Finger" + f + "Prox", side + "Finger" + f + "Dist"
            L.append(Link(prox + "Link", side + "Palm", prox, "revolute",
                          (FINGER_BASE_X, fy, 0), (0, 0, az), (-0.4, 0.8), chain=hand,
                          effort=5, velocity=4.0, damping=0.5, mass=0.03,
                          com=(PROX_LEN / 2, 0, 0), inertia_box=(PROX_LEN / 2, 0.01, 0.012),
                          geoms=[Geom(prox + "Box", "box", (PROX_LEN / 2, 0.01, 0.012),
                                      (PROX_LEN / 2, 0, 0), "grey")]))
            L.append(Link(dist + "Link", prox + "Link", dist, "revolute", (PROX_LEN, 0, 0),
                          (0, 0, az), (0.0, 1.0), chain=hand, effort=5, velocity=4.0,
                          damping=0.5, mass=0.02, com=(DIST_LEN / 2, 0, 0),
                          inertia_box=(DIST_LEN / 2, 0.009, 0.011),
                          geoms=[Geom(dist + "Box", "box", (DIST_LEN / 2, 0.009, 0.011),
                                      (DIST_LEN / 2, 0, 0), "orange")]))
    return L


# Postures (chain -> values in chain order). Checked collision-free with MuJoCo except fist
# (finger-finger contact is expected there).
HAND_OPEN = [-0.3, 0.0, -0.3, 0.0]
POSTURES = {
    "rest": {
        "torso": [0.0],
        "head": [0.0],
        "left_arm": [0.0, 0.15, 0.0, -0.3, 0.0],
        "right_arm": [0.0, -0.15, 0.0, -0.3, 0.0],
        "left_hand": HAND_OPEN,
        "right_hand": HAND_OPEN,
    },
    "hand_open": {"left_hand": HAND_OPEN, "right_hand": HAND_OPEN},
    # Closed gripper: the fingertips meet (1-3 mm finger-finger overlap, nothing else).
    "fist": {"left_hand": [0.4, 0.45, 0.4, 0.45], "right_hand": [0.4, 0.45, 0.4, 0.45]},
    # Right upper arm abducted ~75 deg, forearm up, fingers up, palm normal facing forward.
    "wave_start": {"right_arm": [0.0, -1.3, -1.5708, -1.6, 0.0]},
}

# Left <-> right mirroring: the sign each joint takes on the other side (the left arm's roll,
# elbow yaw and wrist yaw axes act in the opposite sense to the right's for a mirrored pose).
MIRROR_SIGNS = {"arm": [1, -1, -1, 1, -1], "hand": [1, 1, 1, 1]}

# Canned motions: [time_s, joint values...], within SPEED_LIMITS (the loader checks).
WAVE_ARM = lambda elbow_roll: [0.0, -1.3, -1.5708, elbow_roll, 0.0]
CANNED = {
    # Forearm swings side to side from wave_start (elbow roll), three times.
    "wave": (["right_arm"], [[0.0] + WAVE_ARM(-1.6), [0.5] + WAVE_ARM(-1.25),
                             [1.1] + WAVE_ARM(-1.9), [1.7] + WAVE_ARM(-1.25),
                             [2.3] + WAVE_ARM(-1.9), [2.8] + WAVE_ARM(-1.6)]),
    # Bend forward at the torso, hold, come back.
    "bow": (["torso"], [[0.0, 0.0], [1.0, 0.5], [2.0, 0.5], [3.0, 0.0]]),
}


# ----------------------------------------------------------------------------------------
# Helpers.
def fmt(x):
    x = float(x)
    if abs(x) < 1e-15:
        return "0"
    s = repr(x)
    if s.endswith(".0"):
        s = s[:-2]
    return s


def vec(v):
    return " ".join(fmt(x) for x in v)


def rpy_to_quat(rpy):
    """URDF convention: R = Rz(yaw) Ry(pitch) Rx(roll); returns (w, x, y, z)."""
    r, p, y = (a / 2.0 for a in rpy)
    cr, sr, cp, sp, cy, sy = (math.cos(r), math.sin(r), math.cos(p), math.sin(p),
                              math.cos(y), math.sin(y))
    return (cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy)


def is_zero(v):
    return all(abs(x) < 1e-15 for x in v)


def chain_joints(links, chain):
    return [l.joint for l in links if l.chain == chain]


# ----------------------------------------------------------------------------------------
# URDF.
def urdf_geometry(g):
    if g.kind == "box":
        return '<box size="%s"/>' % vec([2 * x for x in g.size])
    if g.kind == "cylinder":
        return '<cylinder radius="%s" length="%s"/>' % (fmt(g.size[0]), fmt(2 * g.size[1]))
    return '<sphere radius="%s"/>' % fmt(g.size[0])


def write_urdf(links, path):
    out = ['<?xml version="1.0"?>',
           "<!-- Generated by tools/minibot/generate.py; do not edit by hand. -->",
           '<robot name="minibot">',
           "  <!-- MuJoCo importer options: keep fixed links (palm frames) as bodies. -->",
           "  <mujoco>",
           '    <compiler fusestatic="false" discardvisual="true" balanceinertia="true"/>',
           "  </mujoco>"]
    for cname, rgba in COLOURS.items():
        out.append('  <material name="%s"><color rgba="%s"/></material>' % (cname, vec(rgba)))
    for l in links:
        out.append('  <link name="%s">' % l.name)
        out.append("    <inertial>")
        out.append('      <origin xyz="%s" rpy="0 0 0"/>' % vec(l.com))
        out.append('      <mass value="%s"/>' % fmt(l.mass))
        out.append('      <inertia ixx="%s" ixy="0" ixz="0" iyy="%s" iyz="0" izz="%s"/>'
                   % tuple(fmt(x) for x in l.inertia))
        out.append("    </inertial>")
        for tag in ("visual", "collision"):
            for g in l.geoms:
                out.append('    <%s name="%s">' % (tag, g.name))
                out.append('      <origin xyz="%s" rpy="0 0 0"/>' % vec(g.pos))
                out.append("      <geometry>%s</geometry>" % urdf_geometry(g))
                if tag == "visual":
                    out.append('      <material name="%s"/>' % g.colour)
                out.append("    </%s>" % tag)
        out.append("  </link>")
    for l in links:
        if l.joint is None:
            continue
        out.append('  <joint name="%s" type="%s">' % (l.joint, l.jtype))
        out.append('    <parent link="%s"/>' % l.parent)
        out.append('    <child link="%s"/>' % l.name)
        out.append('    <origin xyz="%s" rpy="%s"/>' % (vec(l.xyz), vec(l.rpy)))
        if l.jtype != "fixed":
            out.append('    <axis xyz="%s"/>' % vec(l.axis))
            out.append('    <limit lower="%s" upper="%s" effort="%s" velocity="%s"/>'
                       % (fmt(l.rng[0]), fmt(l.rng[1]), fmt(l.effort), fmt(l.velocity)))
            out.append('    <dynamics damping="%s" friction="0"/>' % fmt(l.damping))
        out.append("  </joint>")
    out.append("</robot>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


# ----------------------------------------------------------------------------------------
# MJCF.
def mjcf_geom(g):
    # MuJoCo sizes: box half extents, cylinder (radius, half length), sphere radius.
    size = g.size
    return '<geom name="%s" type="%s" size="%s" pos="%s" rgba="%s"/>' % (
        g.name, g.kind, vec(size), vec(g.pos), vec(COLOURS[g.colour]))


def write_mjcf(links, path):
    children = {}
    for l in links:
        children.setdefault(l.parent, []).append(l)
    out = ["<!-- Generated by tools/minibot/generate.py; do not edit by hand.",
           "     MJCF twin of minibot.urdf: same bodies, joints, frames, inertials, geoms. -->",
           '<mujoco model="minibot">',
           '  <compiler angle="radian" autolimits="true"/>',
           '  <option timestep="0.002"/>',
           "  <worldbody>"]

    def emit(l, depth):
        ind = "  " * depth
        attrs = 'name="%s" pos="%s"' % (l.name, vec(l.xyz if l.xyz else (0, 0, 0)))
        if not is_zero(l.rpy):
            attrs += ' quat="%s"' % vec(rpy_to_quat(l.rpy))
        out.append("%s<body %s>" % (ind, attrs))
        # fullinertia (not diaginertia) so that MuJoCo diagonalises it exactly as it does
        # the URDF <inertia>: both variants compile to identical body_iquat/body_inertia.
        out.append('%s  <inertial pos="%s" mass="%s" fullinertia="%s 0 0 0"/>'
                   % (ind, vec(l.com), fmt(l.mass), vec(l.inertia)))
        if l.jtype in ("revolute", "prismatic"):
            out.append('%s  <joint name="%s" type="%s" axis="%s" range="%s" damping="%s"/>'
                       % (ind, l.joint, "hinge" if l.jtype == "revolute" else "slide",
                          vec(l.axis), vec(l.rng), fmt(l.damping)))
        for g in l.geoms:
            out.append("%s  %s" % (ind, mjcf_geom(g)))
        if l.name in ("LPalm", "RPalm"):
            out.append('%s  <site name="%s" pos="0 0 0" size="0.012" group="3" rgba="0.1 0.8 0.2 0.6"/>'
                       % (ind, l.name))
        if l.name == "Head":
            out.append('%s  <camera name="HeadCam" pos="%s" xyaxes="%s" fovy="%s"/>'
                       % (ind, vec(CAM_POS), vec(CAM_XYAXES), fmt(CAM_FOVY)))
        for c in children.get(l.name, []):
            emit(c, depth + 1)
        out.append("%s</body>" % ind)

    for root in children[None]:
        emit(root, 2)
    out.append("  </worldbody>")
    out.append("  <actuator>")
    for l in links:
        if l.jtype in ("revolute", "prismatic"):
            out.append('    <position name="%s" joint="%s" kp="%s" ctrlrange="%s"/>'
                       % (l.joint, l.joint, fmt(KP[l.chain]), vec(l.rng)))
    out.append("  </actuator>")
    out.append("</mujoco>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


# ----------------------------------------------------------------------------------------
# Profiles.
def height_m():
    return PELVIS_Z + TORSO_JOINT_Z + HEAD_JOINT_Z + HEAD_CENTRE_Z + HEAD_RADIUS


def ylist(values):
    return "[" + ", ".join(fmt(v) for v in values) + "]"


def write_profile(links, path, variant):
    joints = {l.joint: l for l in links if l.joint}
    for pname, posture in POSTURES.items():  # every posture value within the joint range
        for chain, values in posture.items():
            names = chain_joints(links, chain)
            assert len(names) == len(values), (pname, chain)
            for n, v in zip(names, values):
                lo, hi = joints[n].rng
                assert lo <= v <= hi, (pname, n, v, lo, hi)
    out = ["# Generated by tools/minibot/generate.py; do not edit by hand.",
           "name: %s" % variant]
    if variant == "minibot":
        out.append("model: minibot.xml")
    else:
        out.append("urdf: ../minibot/minibot.urdf")
    out.append("description: >-")
    out.append("  Compact child-sized humanoid (NAO-like proportions), kinematically simulated;"
               " planar base, fixed legs, 1-DOF torso and head, 5-DOF arms, two-finger"
               " grippers. minibot (MJCF) and minibot_urdf (URDF) are exact twins.")
    out.append("height_m: %s" % fmt(round(height_m(), 4)))
    out.append("chains:")
    for chain in ("base", "torso", "head", "left_arm", "right_arm", "left_hand",
                  "right_hand"):
        entry = "  %-11s {joints: %s" % (chain + ":", ylist_names(chain_joints(links, chain)))
        if chain in ("left_arm", "right_arm"):
            entry += ", end_effector: %sPalm" % ("L" if chain == "left_arm" else "R")
        out.append(entry + "}")
    if variant == "minibot":
        out.append("head_camera: HeadCam")
    else:
        out.append("head_camera: {name: HeadCam, body: Head, pos: %s, xyaxes: %s, fovy: %s}"
                   % (ylist(CAM_POS), ylist(CAM_XYAXES), fmt(CAM_FOVY)))
    out.append("hands:")
    for side, s in (("left", "L"), ("right", "R")):
        out.append("  %s:" % side)
        out.append("    palm: %sPalm" % s)
        out.append("    approach: [1, 0, 0]        # fingers point at the object")
        out.append("    closing: [0, 1, 0]         # the fingers close along the palm's y axis")
        out.append("    fingers:")
        for f in ("1", "2"):
            j = [s + "Finger" + f + "Prox", s + "Finger" + f + "Dist"]
            out.append("      - {joints: %s, bodies: %s}"
                       % (ylist_names(j), ylist_names([n + "Link" for n in j])))
    out.append("postures:")
    for pname, posture in POSTURES.items():
        out.append("  %s:" % pname)
        for chain, values in posture.items():
            out.append("    %-11s %s" % (chain + ":", ylist(values)))
    out.append("speed_limits:                # per chain: joint velocity (rad/s, m/s) and acceleration")
    for chain, (vel, acc) in SPEED_LIMITS.items():
        out.append("  %-11s {velocity: %s, acceleration: %s}" % (chain + ":", fmt(vel), fmt(acc)))
    out.append("mirror_signs:                # joint signs of a posture moved to the other side")
    for kind, signs in MIRROR_SIGNS.items():
        out.append("  %-11s %s" % (kind + ":", ylist(signs)))
    out.append("canned:                      # keyframes: [time_s, joint values...]")
    for name, (chains, frames) in CANNED.items():
        out.append("  %s:" % name)
        out.append("    chains: %s" % ylist_names(chains))
        out.append("    keyframes:")
        for frame in frames:
            out.append("      - %s" % ylist(frame))
    out.append("actuator_kp:")
    for chain, kp in KP.items():
        out.append("  %-11s %s" % (chain + ":", fmt(kp)))
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def ylist_names(names):
    return "[" + ", ".join(names) + "]"


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", default=os.path.normpath(os.path.join(here, "..", "..")))
    args = ap.parse_args()
    links = build_links()
    names = [l.name for l in links] + [l.joint for l in links if l.joint]
    assert len(names) == len(set(names)), "duplicate link/joint name"
    robot_dir = os.path.join(args.root, "models", "robots", "minibot")
    os.makedirs(robot_dir, exist_ok=True)
    write_urdf(links, os.path.join(robot_dir, "minibot.urdf"))
    write_mjcf(links, os.path.join(robot_dir, "minibot.xml"))
    write_profile(links, os.path.join(robot_dir, "profile.yaml"), "minibot")
    write_profile(links, os.path.join(args.root, "models", "robots", "minibot_urdf",
                                      "profile.yaml"), "minibot_urdf")
    print("wrote minibot.urdf, minibot.xml, profile.yaml (minibot, minibot_urdf) under",
          os.path.join(args.root, "models", "robots"))


if __name__ == "__main__":
    main()

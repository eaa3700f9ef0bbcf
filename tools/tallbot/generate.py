#!/usr/bin/env python3
"""Generates models/robots/tallbot/tallbot.xml (run: python3 tools/tallbot/generate.py).
The profile (profile.yaml) is written by hand and must follow joint name changes. All body frames are world-aligned at qpos0 except the head
(pitched down by CAM_TILT so that the head's +x is the camera's line of sight)."""
import math, sys

import os
OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "..", "models", "robots", "tallbot", "tallbot.xml")
CAM_TILT = math.radians(35.0)

def f(v):
    if abs(abs(v) - 3.14159) < 1e-9:
        return "%.5f" % v
    s = "%.5f" % v
    s = s.rstrip("0").rstrip(".") if "." in s else s
    if s in ("-0", ""):
        s = "0"
    return s

def vec(*v):
    return " ".join(f(x) for x in v)

def norm(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]

def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

def add(a, b, s=1.0):
    return [a[i] + s * b[i] for i in range(3)]

lines = []
ind = [0]
def w(s):
    lines.append("  " * ind[0] + s)
def open_(s):
    w(s); ind[0] += 1
def close(s):
    ind[0] -= 1; w(s)

# ---------------------------------------------------------------- dimensions (world, qpos0)
PELVIS_Z = 0.95
WAIST_Z = 1.00           # torso joints
SHOULDER_Y = 0.20
SHOULDER_Z = 1.42
UPPER = 0.30
FORE = 0.28
NECK_Z = 1.47
HEAD_PIVOT_Z = 1.55

# palm-frame hand description (left hand): x_p along fingers from the wrist, y_p toward the
# thumb, z_p out of the palm surface.
PALM_C = [0.065, 0.0, 0.0]
PALM_H = [0.045, 0.040, 0.014]
FINGER_BASE_X = 0.112
FINGERS = {"index": 0.019, "middle": -0.019}
PROX_LEN, PROX_R = 0.045, 0.0095
DIST_LEN, DIST_R = 0.034, 0.0088
THUMB_B = [0.032, 0.036, 0.010]
TH_OPEN = norm([math.cos(math.radians(50)) * math.cos(math.radians(8)),
                math.sin(math.radians(50)) * math.cos(math.radians(8)),
                math.sin(math.radians(8))])
TH_TARGET = [0.085, 0.0, 0.050]
TH_CLOSED = norm(add(TH_TARGET, THUMB_B, -1))
TH_AXIS = norm(cross(TH_OPEN, TH_CLOSED))
TH_PROX_LEN, TH_PROX_R = 0.040, 0.0105
TH_DIST_LEN, TH_DIST_R = 0.030, 0.0095
PALM_SITE = [0.075, 0.0, 0.050]

def palm_to_body(p, side):
    # left: x_p->(0,0,-1), y_p->(1,0,0), z_p->(0,-1,0); right: mirror y
    s = 1 if side == "l" else -1
    return [p[1], -s * p[2], -p[0]]

def axis_to_body(a, side):
    b = palm_to_body(a, "l")
    return b if side == "l" else [-b[0], b[1], -b[2]]

def mirror_axis(a, side):
    return a if side == "l" else [-a[0], a[1], -a[2]]

# --------------------------------------------------------------------------- model text
w('<mujoco model="tallbot">')
ind[0] += 1
w('<!-- tallbot: a 1.72 m humanoid for the Task Matrix harness, simulated kinematically:')
w('     planar base (x, y, yaw), 2-DOF torso, 2-DOF neck, two 7-DOF arms and three-fingered')
w('     hands (thumb, index, middle; two segments each). Legs are fixed geometry.')
w('     Frames: every body frame is aligned with the world at qpos0 except "head", whose')
w('     +x (the camera line of sight) is pitched 35 degrees down; its geoms are counter-rotated')
w('     so the head looks upright. Sign conventions (same for both sides, axes mirrored):')
w('     shoulder_pitch + raises the arm forward, shoulder_roll + abducts (out to the side),')
w('     shoulder_yaw + rotates the upper arm outward, elbow + flexes, wrist_yaw + supinates,')
w('     wrist_pitch + flexes toward the palm, wrist_roll + deviates toward the thumb,')
w('     finger joints + close. torso_pitch + and neck_pitch + bend/look down (forward).')
w('     Palm sites: +x along the fingers, +z out of the palm, origin where a grasped object\'s')
w('     centre sits. -->')
w('<compiler angle="radian" autolimits="true"/>')
w('<option timestep="0.002"/>')

open_('<default>')
open_('<default class="tallbot">')
w('<geom type="capsule" density="1000" rgba="0.86 0.87 0.89 1" friction="1 0.01 0.001"/>')
w('<joint damping="10" armature="0.05"/>')
w('<position kp="400"/>')
w('<site group="4" rgba="1 0.3 0.3 0.6"/>')
open_('<default class="tb_dark">')
w('<geom rgba="0.18 0.20 0.23 1"/>')
close('</default>')
open_('<default class="tb_visual">')
w('<geom contype="0" conaffinity="0" density="0" rgba="0.08 0.09 0.11 1"/>')
open_('<default class="tb_trim">')
w('<geom rgba="0.20 0.42 0.72 1"/>')
close('</default>')
close('</default>')
open_('<default class="tb_base">')
w('<joint damping="600" armature="1"/>')
w('<position kp="2000"/>')
close('</default>')
open_('<default class="tb_torso">')
w('<joint damping="150" armature="0.5"/>')
w('<position kp="2000"/>')
close('</default>')
open_('<default class="tb_neck">')
w('<joint damping="8" armature="0.05"/>')
w('<position kp="200"/>')
close('</default>')
open_('<default class="tb_shoulder">')
w('<joint damping="30" armature="0.1"/>')
w('<position kp="500"/>')
close('</default>')
open_('<default class="tb_elbow">')
w('<joint damping="15" armature="0.05"/>')
w('<position kp="300"/>')
close('</default>')
open_('<default class="tb_wrist">')
w('<joint damping="5" armature="0.03"/>')
w('<position kp="200"/>')
close('</default>')
open_('<default class="tb_finger">')
w('<joint damping="0.5" armature="0.005"/>')
w('<position kp="30"/>')
w('<geom rgba="0.30 0.32 0.36 1" friction="1.5 0.02 0.002"/>')
close('</default>')
close('</default>')
close('</default>')

actuators = []  # (joint, class, lo, hi)

def joint(name, cls, jtype, axis, lo, hi):
    t = ' type="slide"' if jtype == "slide" else ""
    w('<joint name="%s" class="%s"%s axis="%s" range="%s %s"/>' % (name, cls, t, vec(*axis), f(lo), f(hi)))
    actuators.append((name, cls, lo, hi))

def capsule(name, a, b, r, cls=None):
    c = ' class="%s"' % cls if cls else ""
    w('<geom name="%s"%s fromto="%s" size="%s"/>' % (name, c, vec(*a, *b), f(r)))

def sphere(name, p, r, cls=None):
    c = ' class="%s"' % cls if cls else ""
    w('<geom name="%s"%s type="sphere" pos="%s" size="%s"/>' % (name, c, vec(*p), f(r)))

def box(name, p, h, cls=None, extra=""):
    c = ' class="%s"' % cls if cls else ""
    w('<geom name="%s"%s type="box" pos="%s" size="%s"%s/>' % (name, c, vec(*p), vec(*h), extra))

open_('<worldbody>')
open_('<body name="pelvis" childclass="tallbot" pos="0 0 %s">' % f(PELVIS_Z))
joint("base_x", "tb_base", "slide", [1, 0, 0], -5, 5)
joint("base_y", "tb_base", "slide", [0, 1, 0], -5, 5)
joint("base_yaw", "tb_base", "hinge", [0, 0, 1], -3.14159, 3.14159)
# pelvis and legs (fixed geometry, all in the pelvis body); local z = world z - 0.95
capsule("pelvis", [0, -0.06, 0], [0, 0.06, 0], 0.085)
for s, sy in (("l", 1), ("r", -1)):
    capsule("%s_thigh" % s, [0, sy * 0.085, 0.54 - PELVIS_Z], [0, sy * 0.08, 0.88 - PELVIS_Z], 0.06)
    sphere("%s_knee" % s, [0, sy * 0.087, 0.49 - PELVIS_Z], 0.052, "tb_dark")
    capsule("%s_shin" % s, [0, sy * 0.09, 0.11 - PELVIS_Z], [0, sy * 0.087, 0.45 - PELVIS_Z], 0.047)
    sphere("%s_ankle" % s, [0, sy * 0.09, 0.095 - PELVIS_Z], 0.042, "tb_dark")
    box("%s_foot" % s, [0.045, sy * 0.09, 0.036 - PELVIS_Z], [0.125, 0.048, 0.030])

# torso
open_('<body name="torso" pos="0 0 %s">' % f(WAIST_Z - PELVIS_Z))
joint("torso_yaw", "tb_torso", "hinge", [0, 0, 1], -1.0, 1.0)
# Forward to 1.4 rad (80 degrees): a person's hips and lower back bending with the knees
# straight (the legs are fixed). At 0.8 rad no grasp of an upright object reached below a 0.60 m
# table top (models/README.md, "surface heights").
joint("torso_pitch", "tb_torso", "hinge", [0, 1, 0], -0.3, 1.4)
sphere("waist", [0, 0, 0], 0.075, "tb_dark")
capsule("abdomen", [0, -0.06, 0.09], [0, 0.06, 0.09], 0.08)
w('<geom name="chest" type="ellipsoid" pos="0 0 0.3" size="0.11 0.135 0.17"/>')
w('<geom name="chest_plate" class="tb_trim" type="ellipsoid" pos="0.035 0 0.33" size="0.08 0.1 0.11"/>')
for s, sy in (("l", 1), ("r", -1)):
    capsule("%s_clavicle" % s, [0, sy * 0.05, 0.43], [0, sy * 0.13, SHOULDER_Z - WAIST_Z], 0.045)

# neck and head
open_('<body name="neck" pos="0 0 %s">' % f(NECK_Z - WAIST_Z))
joint("neck_yaw", "tb_neck", "hinge", [0, 0, 1], -1.3, 1.3)
capsule("neck", [0, 0, -0.02], [0, 0, 0.06], 0.045, "tb_dark")
ct, st = math.cos(CAM_TILT), math.sin(CAM_TILT)
def head_local(p):
    # head frame = R_y(tilt); local = R^T p
    return [ct * p[0] - st * p[2], p[1], st * p[0] + ct * p[2]]
hq = "%s 0 %s 0" % (f(math.cos(-CAM_TILT / 2)), f(math.sin(-CAM_TILT / 2)))
open_('<body name="head" pos="0 0 %s" quat="%s 0 %s 0">' % (f(HEAD_PIVOT_Z - NECK_Z), f(math.cos(CAM_TILT / 2)), f(math.sin(CAM_TILT / 2))))
joint("neck_pitch", "tb_neck", "hinge", [0, 1, 0], -0.8, 0.8)
w('<geom name="head" type="ellipsoid" pos="%s" quat="%s" size="0.098 0.078 0.115"/>' % (vec(*head_local([0.015, 0, 0.055])), hq))
w('<geom name="visor" class="tb_visual" type="box" pos="%s" quat="%s" size="0.012 0.056 0.017"/>' % (vec(*head_local([0.099, 0, 0.07])), hq))
for s, sy in (("l", 1), ("r", -1)):
    a = head_local([0.0, sy * 0.07, 0.06]); b = head_local([0.0, sy * 0.086, 0.06])
    w('<geom name="%s_ear" class="tb_trim" type="cylinder" fromto="%s" size="0.025"/>' % (s, vec(*a, *b)))
w('<camera name="head_cam" pos="%s" xyaxes="0 -1 0 0 0 1" fovy="60"/>' % vec(*head_local([0.125, 0, 0.07])))
close('</body>')
close('</body>')

# arms
for s, sy in (("l", 1), ("r", -1)):
    m = lambda a: mirror_axis(a, s)
    open_('<body name="%s_shoulder" pos="0 %s %s">' % (s, f(sy * SHOULDER_Y), f(SHOULDER_Z - WAIST_Z)))
    joint("%s_shoulder_pitch" % s, "tb_shoulder", "hinge", [0, -1, 0], -1.0, 3.05)
    joint("%s_shoulder_roll" % s, "tb_shoulder", "hinge", m([1, 0, 0]), -0.35, 2.9)
    sphere("%s_shoulder" % s, [0, 0, 0], 0.056, "tb_dark")
    open_('<body name="%s_upper_arm">' % s)
    joint("%s_shoulder_yaw" % s, "tb_shoulder", "hinge", m([0, 0, 1]), -1.3, 1.6)
    capsule("%s_upper_arm" % s, [0, 0, -0.08], [0, 0, -0.255], 0.042)
    open_('<body name="%s_forearm" pos="0 0 %s">' % (s, f(-UPPER)))
    joint("%s_elbow" % s, "tb_elbow", "hinge", [0, -1, 0], 0.0, 2.6)
    sphere("%s_elbow" % s, [0, 0, 0], 0.041, "tb_dark")
    capsule("%s_forearm" % s, [0, 0, -0.045], [0, 0, -0.235], 0.034)
    open_('<body name="%s_wrist" pos="0 0 %s">' % (s, f(-FORE)))
    joint("%s_wrist_yaw" % s, "tb_wrist", "hinge", m([0, 0, 1]), -1.5, 1.5)
    joint("%s_wrist_pitch" % s, "tb_wrist", "hinge", axis_to_body([0, -1, 0], s), -1.1, 1.3)
    sphere("%s_wrist" % s, [0, 0, 0], 0.028, "tb_dark")
    open_('<body name="%s_hand">' % s)
    joint("%s_wrist_roll" % s, "tb_wrist", "hinge", axis_to_body([0, 0, 1], s), -0.6, 0.35)
    box("%s_palm" % s, palm_to_body(PALM_C, s), [abs(x) for x in palm_to_body(PALM_H, s)])
    # palm site: x along fingers, z out of the palm
    px = palm_to_body([1, 0, 0], s); pz = palm_to_body([0, 0, 1], s); py = cross(pz, px)
    w('<site name="%s_palm" pos="%s" xyaxes="%s" size="0.012"/>' % (s, vec(*palm_to_body(PALM_SITE, s)), vec(*px, *py)))
    # thumb
    tb = palm_to_body(THUMB_B, s)
    td = palm_to_body(TH_OPEN, s)
    ta = axis_to_body(TH_AXIS, s)
    open_('<body name="%s_thumb_prox" pos="%s">' % (s, vec(*tb)))
    joint("%s_thumb_prox" % s, "tb_finger", "hinge", ta, 0.0, 1.5)
    capsule("%s_thumb_prox" % s, [x * 0.004 for x in td], [x * (TH_PROX_LEN - 0.008) for x in td], TH_PROX_R, "tb_finger")
    open_('<body name="%s_thumb_dist" pos="%s">' % (s, vec(*[x * TH_PROX_LEN for x in td])))
    joint("%s_thumb_dist" % s, "tb_finger", "hinge", ta, 0.0, 1.3)
    capsule("%s_thumb_dist" % s, [0, 0, 0], [x * (TH_DIST_LEN - TH_DIST_R) for x in td], TH_DIST_R, "tb_finger")
    close('</body>')
    close('</body>')
    # fingers
    fx = palm_to_body([1, 0, 0], s)
    for fname, fy in FINGERS.items():
        base = palm_to_body([FINGER_BASE_X, fy, 0], s)
        open_('<body name="%s_%s_prox" pos="%s">' % (s, fname, vec(*base)))
        joint("%s_%s_prox" % (s, fname), "tb_finger", "hinge", axis_to_body([0, -1, 0], s), 0.0, 1.6)
        capsule("%s_%s_prox" % (s, fname), [0, 0, 0], [x * (PROX_LEN - 0.009) for x in fx], PROX_R, "tb_finger")
        open_('<body name="%s_%s_dist" pos="%s">' % (s, fname, vec(*[x * PROX_LEN for x in fx])))
        joint("%s_%s_dist" % (s, fname), "tb_finger", "hinge", axis_to_body([0, -1, 0], s), 0.0, 1.7)
        capsule("%s_%s_dist" % (s, fname), [0, 0, 0], [x * (DIST_LEN - DIST_R) for x in fx], DIST_R, "tb_finger")
        close('</body>')
        close('</body>')
    close('</body>')  # hand
    close('</body>')  # wrist
    close('</body>')  # forearm
    close('</body>')  # upper arm
    close('</body>')  # shoulder

close('</body>')  # torso
close('</body>')  # pelvis
close('</worldbody>')

open_('<actuator>')
for name, cls, lo, hi in actuators:
    w('<position name="%s" class="%s" joint="%s" ctrlrange="%s %s"/>' % (name, cls, name, f(lo), f(hi)))
close('</actuator>')
ind[0] -= 1
w('</mujoco>')

open(OUT, "w").write("\n".join(lines) + "\n")
print("thumb open", [round(x, 3) for x in TH_OPEN], "closed", [round(x, 3) for x in TH_CLOSED],
      "axis", [round(x, 3) for x in TH_AXIS], "angle", round(math.acos(sum(a * b for a, b in zip(TH_OPEN, TH_CLOSED))), 3))

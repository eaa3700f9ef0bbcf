#!/usr/bin/env python3
"""valbot: a humanoid with NASA Valkyrie (R5)'s published kinematics, for the Task Matrix
harness's tests (a robot the programs were not written for). Joint origins, axes and limits are
written below as numbers; collision shapes are primitives sized after the robot. Legs are fixed
straight geometry; planar base. Writes valbot.xml next to this file. Plain Python (no numpy)."""
import math, os

HERE = os.path.dirname(os.path.abspath(__file__))

# ---------------------------------------------------------------- small helpers
def qmul(a, b):
    w1, x1, y1, z1 = a; w2, x2, y2, z2 = b
    return (w1*w2 - x1*x2 - y1*y2 - z1*z2, w1*x2 + x1*w2 + y1*z2 - z1*y2,
            w1*y2 - x1*z2 + y1*w2 + z1*x2, w1*z2 + x1*y2 - y1*x2 + z1*w2)

def qaxis(ax, ang):
    s = math.sin(ang / 2)
    return (math.cos(ang / 2), ax[0]*s, ax[1]*s, ax[2]*s)

def rpy_quat(r, p, y):  # URDF: R = Rz(y) Ry(p) Rx(r)
    return qmul(qaxis((0, 0, 1), y), qmul(qaxis((0, 1, 0), p), qaxis((1, 0, 0), r)))

def qrot(q, v):
    w, x, y, z = q
    p = (0, v[0], v[1], v[2])
    r = qmul(qmul(q, p), (w, -x, -y, -z))
    return r[1:]

def f(*v):
    return " ".join(("%.6g" % x) if abs(x) > 1e-12 else "0" for x in v)

def geom(name, cls=None, **kw):
    a = ['name="%s"' % name]
    if cls: a.append('class="%s"' % cls)
    for k, v in kw.items():
        a.append('%s="%s"' % (k, v if isinstance(v, str) else f(*v) if isinstance(v, (tuple, list)) else f(v)))
    return "<geom %s/>" % " ".join(a)

# ---------------------------------------------------------------- joints (URDF)
# Left side as in the URDF; the right side is mirrored (y -> -y), axes and limits as the URDF's.
L = dict(
    ShoulderPitch=dict(xyz=(-0.0316, 0.0, 0.2984), axis=(0, 1, 0), lim=(-2.85, 2.0)),
    ShoulderRoll=dict(xyz=(0.0, 0.2499, 0.0), axis=(1, 0, 0), lim=(-1.519, 1.266)),
    ShoulderYaw=dict(xyz=(0, 0, 0), axis=(0, 1, 0), lim=(-3.1, 2.18)),
    ElbowPitch=dict(xyz=(0.0254, 0.33, 0.0), axis=(0, 0, 1), lim=(-2.174, 0.12)),
    ForearmYaw=dict(xyz=(-0.0254, 0, 0), axis=(0, 1, 0), lim=(-2.019, 3.14)),
    WristRoll=dict(xyz=(0.0, 0.2871, 0.0), axis=(1, 0, 0), lim=(-0.62, 0.625)),
    WristPitch=dict(xyz=(0, 0, 0), axis=(0, 0, 1), lim=(-0.36, 0.49)),
)
R = dict(
    ShoulderRoll=(-1.266, 1.519), ElbowPitch=(-0.12, 2.174), WristRoll=(-0.625, 0.62),
    WristPitch=(-0.49, 0.36), ShoulderPitch=(-2.85, 2.0), ShoulderYaw=(-3.1, 2.18),
    ForearmYaw=(-2.019, 3.14))

def side_lim(side, j, lim):
    return lim if side == "left" else R.get(j, lim)

def mir(v, side):
    return v if side == "left" else (v[0], -v[1], v[2])

out = []
def w(s, ind):
    out.append("  " * ind + s)

def joint(name, cls, axis, lim):
    return '<joint name="%s" class="%s" axis="%s" range="%s"/>' % (name, cls, f(*axis), f(*lim))

ACT = []  # (name, class, range)

def J(ind, name, cls, axis, lim):
    w(joint(name, cls, axis, lim), ind)
    ACT.append((name, cls, lim))

def arm(side, ind):
    s = 1 if side == "left" else -1
    P = side
    def pos(v): return f(*mir(v, side))
    w('<body name="%sShoulderPitchLink" pos="%s">' % (P, pos(L["ShoulderPitch"]["xyz"])), ind)
    J(ind+1, P + "ShoulderPitch", "vb_shoulder", (0, 1, 0), side_lim(side, "ShoulderPitch", L["ShoulderPitch"]["lim"]))
    w(geom(P + "ShoulderPitchLink", "vb_dark", type="cylinder", fromto=(0, s*0.15, 0, 0, s*0.19, 0), size=0.062), ind+1)
    w('<body name="%sShoulderRollLink" pos="%s">' % (P, pos(L["ShoulderRoll"]["xyz"])), ind+1)
    J(ind+2, P + "ShoulderRoll", "vb_shoulder", (1, 0, 0), side_lim(side, "ShoulderRoll", L["ShoulderRoll"]["lim"]))
    w(geom(P + "ShoulderRollLink", "vb_dark", type="sphere", pos=(0, 0, 0), size=0.06), ind+2)
    w('<body name="%sShoulderYawLink">' % P, ind+2)
    J(ind+3, P + "ShoulderYaw", "vb_shoulder", (0, 1, 0), side_lim(side, "ShoulderYaw", L["ShoulderYaw"]["lim"]))
    w(geom(P + "UpperArm", fromto=(0, s*0.075, 0, 0, s*0.27, 0), size=0.052), ind+3)
    w('<body name="%sElbowPitchLink" pos="%s">' % (P, pos(L["ElbowPitch"]["xyz"])), ind+3)
    J(ind+4, P + "ElbowPitch", "vb_elbow", (0, 0, 1), side_lim(side, "ElbowPitch", L["ElbowPitch"]["lim"]))
    w(geom(P + "Elbow", "vb_dark", type="cylinder", fromto=(0, 0, -0.045, 0, 0, 0.045), size=0.045), ind+4)
    w('<body name="%sForearmLink" pos="%s">' % (P, pos(L["ForearmYaw"]["xyz"])), ind+4)
    J(ind+5, P + "ForearmYaw", "vb_elbow", (0, 1, 0), side_lim(side, "ForearmYaw", L["ForearmYaw"]["lim"]))
    w(geom(P + "Forearm", "vb_red", fromto=(0, s*0.07, 0, 0, s*0.22, 0), size=0.046), ind+5)
    w('<body name="%sWristRollLink" pos="%s">' % (P, pos(L["WristRoll"]["xyz"])), ind+5)
    J(ind+6, P + "WristRoll", "vb_wrist", (1, 0, 0), side_lim(side, "WristRoll", L["WristRoll"]["lim"]))
    w(geom(P + "Wrist", "vb_dark", type="sphere", pos=(0, 0, 0), size=0.028), ind+6)
    w('<body name="%sPalm">' % P, ind+6)
    J(ind+7, P + "WristPitch", "vb_wrist", (0, 0, 1), side_lim(side, "WristPitch", L["WristPitch"]["lim"]))
    hand(side, ind+7)
    w('</body>', ind+6)
    for k in range(6):
        w('</body>', ind+5-k)

def hand(side, ind):
    s = 1 if side == "left" else -1
    P = side
    # palm: fingers along +y (left) / -y (right), palm normal +x, thumb on the +z side.
    # The palm's face is at x = 0.004, just ahead of the fingers' knuckle line (x = 0.0022).
    w(geom(P + "PalmBox", "vb_hand", type="box", pos=(-0.014, s*0.055, -0.008), size=(0.018, 0.038, 0.045)), ind)
    # palm frame: the grasp centre, 4.6 cm out of the palm and between thumb and fingers.
    # Site axes = the palm body's axes.
    w('<site name="%s_palm" pos="%s" size="0.012"/>' % (P, f(0.046, s*0.066, -0.006)), ind)
    # thumb: roll (URDF ThumbRoll), pitch1, pitch2 (pitch2 and pitch3 merged into one distal)
    tq = rpy_quat(-0.3491*s, 0, 0)
    w('<body name="%sThumbRollLink" pos="%s" quat="%s">' % (P, f(0.0049, s*0.0351, 0.0228), f(*tq)), ind)
    J(ind+1, P + "ThumbRoll", "vb_finger", (0, 1, 0), (0.0, 2.356))
    w(geom(P + "ThumbRollLink", "vb_finger", fromto=(0, 0, 0.004, 0, 0, 0.016), size=0.011), ind+1)
    w('<body name="%sThumbPitch1Link" pos="0 0 0.0229" quat="%s">' % (P, f(*rpy_quat(0.3491*s, 0, 0))), ind+1)
    J(ind+2, P + "ThumbPitch1", "vb_finger", (1, 0, 0), (-1.658, 0.0) if s > 0 else (0.0, 1.658))
    w(geom(P + "ThumbPitch1Link", "vb_finger", fromto=(0, s*0.002, 0.012, 0, s*0.0062, 0.0345), size=0.0105), ind+2)
    w('<body name="%sThumbPitch2Link" pos="%s">' % (P, f(0, s*0.0066, 0.0375)), ind+2)
    J(ind+3, P + "ThumbPitch2", "vb_finger", (1, 0, 0), (-1.92, 0.0) if s > 0 else (0.0, 1.92))
    w(geom(P + "ThumbPitch2Link", "vb_finger", fromto=(0, s*0.001, 0.004, 0, s*0.008, 0.044), size=0.0095), ind+3)
    w('</body>', ind+2); w('</body>', ind+1); w('</body>', ind)
    # index, middle, pinky: three pitches each about z, URDF origins and splay
    fingers = [("IndexFinger", (0.0022, 0.0976, 0.0235), 0.1745, [(-1.57, 0), (-1.658, 0), (-1.92, 0)]),
               ("MiddleFinger", (0.0022, 0.097, -0.0119), -0.1222, [(-1.658, 0), (-1.92, 0), (-1.57, 0)]),
               ("Pinky", (0.0022, 0.0838, -0.041), -0.1222, [(-1.57, 0), (-1.658, 0), (-1.92, 0)])]
    for fname, xyz, splay, lims in fingers:
        def lim(l): return l if s > 0 else (-l[1], -l[0])
        w('<body name="%s%sPitch1Link" pos="%s" quat="%s">' % (P, fname, f(xyz[0], s*xyz[1], xyz[2]), f(*rpy_quat(splay*s, 0, 0))), ind)
        J(ind+1, "%s%sPitch1" % (P, fname), "vb_finger", (0, 0, 1), lim(lims[0]))
        w(geom("%s%sPitch1Link" % (P, fname), "vb_finger", fromto=(0, s*0.004, 0, 0, s*0.031, 0), size=0.0095), ind+1)
        w('<body name="%s%sPitch2Link" pos="%s">' % (P, fname, f(0, s*0.0381, 0)), ind+1)
        J(ind+2, "%s%sPitch2" % (P, fname), "vb_finger", (0, 0, 1), lim(lims[1]))
        w(geom("%s%sPitch2Link" % (P, fname), "vb_finger", fromto=(0, s*0.003, 0, 0, s*0.0165, 0), size=0.009), ind+2)
        w('<body name="%s%sPitch3Link" pos="%s">' % (P, fname, f(0, s*0.0229, 0)), ind+2)
        J(ind+3, "%s%sPitch3" % (P, fname), "vb_finger", (0, 0, 1), lim(lims[2]))
        w(geom("%s%sPitch3Link" % (P, fname), "vb_finger", fromto=(0, s*0.003, 0, 0, s*0.02, 0), size=0.0085), ind+3)
        w('</body>', ind+2); w('</body>', ind+1); w('</body>', ind)

# ---------------------------------------------------------------- model
PELVIS_Z = 1.176  # soles (foot box bottom 1.171 below the pelvis) 5 mm above the floor

def model():
    w('<body name="pelvis" childclass="valbot" pos="0 0 %g">' % PELVIS_Z, 2)
    for n, t, ax, rng in (("base_x", "slide", (1, 0, 0), (-5, 5)), ("base_y", "slide", (0, 1, 0), (-5, 5)),
                          ("base_yaw", "hinge", (0, 0, 1), (-3.14159, 3.14159))):
        w('<joint name="%s" class="vb_base" type="%s" axis="%s" range="%s"/>' % (n, t, f(*ax), f(*rng)), 3)
        ACT.append((n, "vb_base", rng))
    w(geom("pelvis", "vb_dark", type="box", pos=(-0.02, 0, -0.125), size=(0.11, 0.15, 0.05)), 3)
    for s, P in ((1, "left"), (-1, "right")):
        hip = (0, s*0.1016, -0.1853 - 0.0609)        # hip pitch joint
        knee = (0.000112, s*(0.1016 + 0.0361), hip[2] - 0.430959)
        ankle = (knee[0] - 0.0102381, knee[1], knee[2] - 0.40627)
        w(geom(P + "Hip", "vb_dark", type="sphere", pos=hip, size=0.075), 3)
        w(geom(P + "Thigh", fromto=(hip[0], hip[1], hip[2] - 0.06, knee[0], knee[1], knee[2] + 0.07), size=0.072), 3)
        w(geom(P + "Knee", "vb_dark", type="sphere", pos=knee, size=0.062), 3)
        w(geom(P + "Shin", "vb_red", fromto=(knee[0], knee[1], knee[2] - 0.07, ankle[0], ankle[1], ankle[2] + 0.06), size=0.058), 3)
        w(geom(P + "Ankle", "vb_dark", type="sphere", pos=ankle, size=0.04), 3)
        # URDF foot collision box 0.27 x 0.16 x 0.064 at (0.045, 0, -0.056) from the ankle
        w(geom(P + "Foot", "vb_dark", type="box", pos=(ankle[0] + 0.045, ankle[1], ankle[2] - 0.056), size=(0.135, 0.08, 0.032)), 3)
    # waist: torsoYaw at the pelvis origin, torsoPitch 0.04191 forward, torsoRoll 0.0203 up
    w('<body name="torsoYawLink">', 3)
    J(4, "torsoYaw", "vb_torso", (0, 0, 1), (-1.329, 1.181))
    w('<inertial pos="0 0 0" mass="2.5" diaginertia="0.01 0.01 0.01"/>', 4)  # no shape of its own
    w('<body name="torsoPitchLink" pos="0.04191 0 0">', 4)
    J(5, "torsoPitch", "vb_torso", (0, 1, 0), (-0.13, 0.666))
    w(geom("abdomen", "vb_dark", fromto=(0, -0.1, 0, 0, 0.1, 0), size=0.055), 5)
    w('<body name="torso" pos="0 0 0.0203">', 5)
    J(6, "torsoRoll", "vb_torso", (1, 0, 0), (-0.23, 0.255))
    w(geom("chest", type="box", pos=(-0.035, 0, 0.21), size=(0.14, 0.165, 0.125)), 6)
    w(geom("chest_plate", "vb_visual", type="box", pos=(0.09, 0, 0.23), size=(0.018, 0.11, 0.08)), 6)
    w(geom("backpack", "vb_dark", type="box", pos=(-0.225, 0, 0.19), size=(0.05, 0.13, 0.14)), 6)
    # neck: lowerNeckPitch, neckYaw, upperNeckPitch (URDF origins)
    w('<body name="lowerNeckPitchLink" pos="0.0203518 0 0.33845">', 6)
    J(7, "lowerNeckPitch", "vb_neck", (0, 1, 0), (0.0, 1.162))
    w(geom("lowerNeck", "vb_dark", type="sphere", pos=(-0.02, 0, 0), size=0.035), 7)
    w('<body name="neckYawLink" pos="-0.051924 0 0">', 7)
    J(8, "neckYaw", "vb_neck", (0, 0, 1), (-1.04719755, 1.04719755))
    w(geom("neck", "vb_dark", fromto=(-0.012, 0, 0.058, -0.05, 0, 0.15), size=0.045), 8)
    w('<body name="upperNeckPitchLink" pos="-0.06 0 0.195997">', 8)
    J(9, "upperNeckPitch", "vb_neck", (0, 1, 0), (-0.872, 0.0))
    w(geom("head", type="ellipsoid", pos=(0.06, 0, 0.05), size=(0.115, 0.1, 0.105)), 9)
    w(geom("visor", "vb_visual", type="ellipsoid", pos=(0.125, 0, 0.07), size=(0.05, 0.085, 0.05)), 9)
    w(geom("lens", "vb_visual", type="cylinder", fromto=(0.17, 0, 0.0767, 0.176, 0, 0.0759), size=0.012), 9)
    # MultiSense head frame: (0.183586, 0, 0.075354), rpy (-pi, 0.1309, 0); camera between the
    # stereo pair (0, +-0.035, -0.002) in it, looking along the head's +x (7.5 deg down)
    hq = rpy_quat(-3.14159, 0.130899694, 0)
    c = qrot(hq, (0, 0, -0.002))
    cam = (0.183586 + c[0], c[1], 0.075354 + c[2])
    up = qrot(hq, (0, 0, -1))  # the head frame is upside down: its -z is up
    w('<camera name="head_cam" pos="%s" xyaxes="0 -1 0 %s" fovy="64.366444"/>' % (f(*cam), f(*up)), 9)
    w('</body>', 8); w('</body>', 7); w('</body>', 6)
    arm("left", 6)
    arm("right", 6)
    w('</body>', 5); w('</body>', 4); w('</body>', 3)
    w('</body>', 2)

HEADER = '''<mujoco model="valbot">
  <!-- valbot: a humanoid with NASA Valkyrie (R5)'s published kinematics (generate.py, which
       writes this file, holds the numbers). Planar base (x, y, yaw), fixed straight legs,
       3-DOF waist (torsoYaw, torsoPitch, torsoRoll), 3-DOF neck (lowerNeckPitch, neckYaw,
       upperNeckPitch), two 7-DOF arms, hands with a 3-joint thumb and index, middle and pinky
       fingers of three pitches. Joint names, origins, axes and limits are the URDF's; qpos0 is
       the URDF zero (arms straight out to the sides). Palm sites: frame = palm body frame
       (+x out of the palm, fingers along +y left / -y right, thumb on +z). -->
  <compiler angle="radian" autolimits="true"/>
  <option timestep="0.002"/>
  <default>
    <default class="valbot">
      <geom type="capsule" density="1000" rgba="0.93 0.93 0.93 1" friction="1 0.01 0.001"/>
      <joint damping="10" armature="0.05"/>
      <position kp="400"/>
      <site group="4" rgba="1 0.3 0.3 0.6"/>
      <default class="vb_dark"><geom rgba="0.15 0.15 0.17 1"/></default>
      <default class="vb_red"><geom rgba="0.65 0.1 0.1 1"/></default>
      <default class="vb_hand"><geom rgba="0.2 0.2 0.22 1"/></default>
      <default class="vb_visual"><geom contype="0" conaffinity="0" density="0" rgba="0.05 0.05 0.06 1"/></default>
      <default class="vb_base"><joint damping="600" armature="1"/><position kp="2000"/></default>
      <default class="vb_torso"><joint damping="200" armature="0.5"/><position kp="3000"/></default>
      <default class="vb_neck"><joint damping="8" armature="0.05"/><position kp="200"/></default>
      <default class="vb_shoulder"><joint damping="30" armature="0.1"/><position kp="600"/></default>
      <default class="vb_elbow"><joint damping="15" armature="0.05"/><position kp="400"/></default>
      <default class="vb_wrist"><joint damping="5" armature="0.03"/><position kp="200"/></default>
      <default class="vb_finger">
        <joint damping="0.5" armature="0.005"/><position kp="30"/>
        <geom rgba="0.25 0.25 0.27 1" friction="1.5 0.02 0.002"/>
      </default>
    </default>
  </default>
  <worldbody>'''

def main():
    out.append(HEADER)
    model()
    out.append("  </worldbody>")
    out.append("  <actuator>")
    for n, cls, rng in ACT:
        out.append('    <position name="%s" class="%s" joint="%s" ctrlrange="%s"/>' % (n, cls, n, f(*rng)))
    out.append("  </actuator>")
    out.append("</mujoco>")
    with open(os.path.join(HERE, "valbot.xml"), "w") as fh:
        fh.write("\n".join(out) + "\n")

main()

#!/usr/bin/env python3
"""Generates models/environments/{kitchen,office}/*.xml (run: python3 tools/environments/generate.py).
The environment.yaml files are written by hand and must follow name and position changes."""
import math, sys

def f(x):
    s = f"{x:.4f}".rstrip('0').rstrip('.')
    return "0" if s in ("-0", "") else s

def v(*xs):
    return " ".join(f(x) for x in xs)

def norm(a):
    n = math.sqrt(sum(c * c for c in a)); return [c / n for c in a]

def cross(a, b):
    return [a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0]]

def lookat(pos, target):
    fwd = norm([t - p for t, p in zip(target, pos)])
    x = norm(cross(fwd, [0, 0, 1]))
    y = cross(x, fwd)  # camera y (up in image); camera looks along -z = fwd
    return v(*x, *y)

class W:
    def __init__(self):
        self.lines = []; self.ind = 0
    def o(self, s):
        self.lines.append(("  " * self.ind + s) if s else "")
    def open(self, s):
        self.o(s); self.ind += 1
    def close(self, s):
        self.ind -= 1; self.o(s)
    def text(self):
        return "\n".join(self.lines) + "\n"

def boxg(w, name, lo, hi, mat=None, rgba=None, origin=(0, 0, 0), extra=""):
    """Axis-aligned box from world corners lo/hi, written relative to origin."""
    c = [(a + b) / 2 - o for a, b, o in zip(lo, hi, origin)]
    h = [(b - a) / 2 for a, b in zip(lo, hi)]
    assert all(x > 0 for x in h), (name, lo, hi)
    look = f' material="{mat}"' if mat else (f' rgba="{rgba}"' if rgba else "")
    nm = f' name="{name}"' if name else ""
    w.o(f'<geom{nm} type="box" pos="{v(*c)}" size="{v(*h)}"{look}{extra}/>')

def geom(w, name, typ, look, extra, **kw):
    nm = f' name="{name}"' if name else ""
    attrs = "".join(f' {k}="{val}"' for k, val in kw.items())
    lk = ""
    if look:
        lk = f' material="{look}"' if not look[0].isdigit() and not look[0] == '.' else f' rgba="{look}"'
    w.o(f'<geom{nm} type="{typ}"{attrs}{lk}{extra}/>')

# ----------------------------------------------------------------------------------------
ROOM_X = (-2.5, 3.5); ROOM_Y = (-3.0, 3.0); WALL_H = 2.5; WALL_T = 0.1

DESC = {
 "kitchen": """Task Matrix environment "kitchen" (no robot; the loader composes one in at the origin, facing +x).
     Room: floor z = 0, walls at x = -2.5 / 3.5 and y = -3 / 3.
     table (main work surface): top z = 0.65, x [0.30, 1.00], y [-0.60, 0.60]; body origin = centre of the top face.
     counter (put-down surface, robot's left): top z = 0.68, x [-0.35, 0.25], y [0.55, 1.00].
     On the table: cup (0.42, -0.12), box (0.42, 0.15), vacuum (origin 0.57, -0.40; grip 0.51, tip 0.74), debris_0..4
     in x [0.45, 0.65], y [0.25, 0.50]. Visitor at (2.5, -1.0) facing the robot.
     Fridge, base/wall cabinets, sink and hob along the y = +3 wall; chair at (-1.7, -0.3); waste bin at (-1.9, -2.6).
     Open floor for random obstacles: x [1.15, 3.1], y [-2, 2]. Within 0.45 m of the origin: only the table top and the objects on it.""",
 "office": """Task Matrix environment "office" (no robot; the loader composes one in at the origin, facing +x).
     Room: floor z = 0, walls at x = -2.5 / 3.5 and y = -3 / 3.
     desk (main work surface): top z = 0.65, x [0.30, 1.05], y [-0.65, 0.65]; body origin = centre of the top face;
     monitor at its back left (x >= 0.89, y [0.07, 0.63]).
     side_table (put-down surface, robot's left): top z = 0.64, x [-0.25, 0.25], y [0.55, 1.00].
     On the desk: cup (0.42, -0.12), box (0.42, 0.15), vacuum (origin 0.57, -0.40; grip 0.51, tip 0.74), debris_0..4
     in x [0.45, 0.65], y [0.25, 0.50]. Visitor at (2.5, -1.0) facing the robot.
     Bookshelf along the y = -3 wall, filing cabinet at the y = +3 wall, office chair at (-1.6, -0.2), plant at (-2.15, -2.6).
     Open floor for random obstacles: x [1.15, 3.1], y [-2, 2]. Within 0.45 m of the origin: only the desk top and the objects on it.""",
}

def header(w, env, floor_rgb, floor_rgb2, wall_rgb, sky):
    w.o("<!-- " + DESC[env] + " -->")
    w.open(f'<mujoco model="{env}">')
    w.o('<compiler angle="radian" autolimits="true"/>')
    w.o('')
    w.open('<visual>')
    w.o('<global offwidth="1280" offheight="960"/>')
    w.o('<quality shadowsize="4096"/>')
    w.o('<headlight ambient="0.3 0.3 0.3" diffuse="0.4 0.4 0.4" specular="0.1 0.1 0.1"/>')
    w.o('<map znear="0.01" zfar="50"/>')
    w.close('</visual>')
    w.o('')

def walls(w, env, mat):
    x0, x1 = ROOM_X; y0, y1 = ROOM_Y; t = WALL_T; h = WALL_H
    w.o(f'<!-- room walls: inner faces at x = {f(x0)} / {f(x1)}, y = {f(y0)} / {f(y1)}, {f(h)} m high -->')
    boxg(w, f"{env}_wall_back", (x0 - t, y0 - t, 0), (x0, y1 + t, h), mat)
    boxg(w, f"{env}_wall_front", (x1, y0 - t, 0), (x1 + t, y1 + t, h), mat)
    boxg(w, f"{env}_wall_right", (x0, y0 - t, 0), (x1, y0, h), mat)
    boxg(w, f"{env}_wall_left", (x0, y1, 0), (x1, y1 + t, h), mat)

def floor_and_lights(w, env):
    cx = (ROOM_X[0] + ROOM_X[1]) / 2; hx = (ROOM_X[1] - ROOM_X[0]) / 2; hy = (ROOM_Y[1] - ROOM_Y[0]) / 2
    w.o(f'<geom name="{env}_floor" type="plane" pos="{v(cx, 0, 0)}" size="{v(hx, hy, 0.05)}" material="{env}_floor_mat"/>')
    w.o(f'<light name="{env}_sun" directional="true" pos="0.5 -0.5 3" dir="0.25 0.35 -1" castshadow="true" diffuse="0.55 0.55 0.52" specular="0.2 0.2 0.2"/>')
    w.o(f'<light name="{env}_fill" directional="true" pos="0 1 3" dir="-0.3 -0.4 -1" castshadow="false" diffuse="0.3 0.3 0.32" specular="0 0 0"/>')

def cameras(w):
    ov_pos, ov_t = (-1.6, -1.8, 2.0), (0.5, 0.0, 0.7)
    sd_pos, sd_t = (0.9, -2.75, 1.35), (0.9, 0.0, 0.75)
    fr_pos, fr_t = (2.9, -0.3, 1.7), (0.0, 0.0, 0.95)
    w.o('<!-- scene cameras (fixed; xyaxes computed from a look-at point, given in the comment) -->')
    w.o(f'<camera name="overview" mode="fixed" pos="{v(*ov_pos)}" xyaxes="{lookat(ov_pos, ov_t)}" fovy="50"/>  <!-- looks at {v(*ov_t)} -->')
    w.o(f'<camera name="side" mode="fixed" pos="{v(*sd_pos)}" xyaxes="{lookat(sd_pos, sd_t)}" fovy="55"/>  <!-- looks at {v(*sd_t)} -->')
    w.o(f'<camera name="front" mode="fixed" pos="{v(*fr_pos)}" xyaxes="{lookat(fr_pos, fr_t)}" fovy="50"/>  <!-- looks at {v(*fr_t)} -->')

# ----------------------------------------------------------------------------------------
def surface_table(w, body, top, x0, x1, y0, y1, thick, mat_top, mat_leg, leg=0.05, inset=0.03, apron=True, label="table"):
    """Four-legged table. Body origin = centre of the top face."""
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2; O = (cx, cy, top)
    w.o(f'<!-- {label}: top face z = {f(top)}, x [{f(x0)}, {f(x1)}], y [{f(y0)}, {f(y1)}]; body origin = centre of the top face -->')
    w.open(f'<body name="{body}" pos="{v(cx, cy, top)}">')
    boxg(w, f"{body}_top", (x0, y0, top - thick), (x1, y1, top), mat_top, origin=O)
    lx = [x0 + inset, x1 - inset - leg]; ly = [y0 + inset, y1 - inset - leg]
    i = 0
    for ax in lx:
        for ay in ly:
            boxg(w, f"{body}_leg_{i}", (ax, ay, 0), (ax + leg, ay + leg, top - thick), mat_leg, origin=O); i += 1
    if apron:
        az0, az1 = top - thick - 0.08, top - thick
        boxg(w, f"{body}_apron_0", (lx[0] + leg, ly[0] + 0.01, az0), (lx[1], ly[0] + 0.03, az1), mat_leg, origin=O)
        boxg(w, f"{body}_apron_1", (lx[0] + leg, ly[1] + leg - 0.03, az0), (lx[1], ly[1] + leg - 0.01, az1), mat_leg, origin=O)
        boxg(w, f"{body}_apron_2", (lx[1] + leg - 0.03, ly[0] + leg, az0), (lx[1] + leg - 0.01, ly[1], az1), mat_leg, origin=O)
    w.o(f'<site name="{body}_surface" type="box" pos="0 0 0" size="{v((x1 - x0) / 2, (y1 - y0) / 2, 0.001)}" rgba="0 0 0 0"/>')
    w.close('</body>')

def cup(w, x, y, top, mat, label="cup"):
    r, hh = 0.038, 0.05
    w.o(f'<!-- cup: cylinder r {f(r)}, height {f(2 * hh)}, bottom at z = {f(top)} (on the surface); base pad gives a stable box-box support -->')
    w.open(f'<body name="cup" pos="{v(x, y, top + hh)}">')
    w.o('<freejoint name="cup_free"/>')
    w.o(f'<geom name="cup_shell" type="cylinder" size="{v(r, hh)}" mass="0.22" material="{mat}" friction="1 0.01 0.001"/>')
    w.o(f'<geom name="cup_base" type="box" pos="{v(0, 0, -hh + 0.003)}" size="0.026 0.026 0.003" mass="0.01" material="{mat}" friction="1 0.01 0.001"/>')
    w.o(f'<geom name="cup_coffee" type="cylinder" pos="0 0 {f(hh - 0.012)}" size="{v(r - 0.004, 0.0105)}" rgba="0.25 0.13 0.05 1" contype="0" conaffinity="0" mass="0.001"/>')
    w.close('</body>')

def juicebox(w, x, y, top, mat, straw):
    hx, hy, hz = 0.025, 0.025, 0.06
    w.o(f'<!-- box: juice box {f(2*hx)} x {f(2*hy)} x {f(2*hz)}, bottom at z = {f(top)} -->')
    w.open(f'<body name="box" pos="{v(x, y, top + hz)}">')
    w.o('<freejoint name="box_free"/>')
    w.o(f'<geom name="box_body" type="box" size="{v(hx, hy, hz)}" mass="0.25" material="{mat}" friction="1 0.01 0.001"/>')
    w.o(f'<geom name="box_straw" type="capsule" fromto="{v(0.012, 0.01, hz - 0.002, 0.016, 0.012, hz + 0.035)}" size="0.003" rgba="{straw}" contype="0" conaffinity="0" mass="0.001"/>')
    w.close('</body>')

def vacuum(w, x, y, top, m_body, m_dark, m_accent):
    """Handheld vacuum lying on the surface, nozzle along its local +x. Origin on the surface."""
    w.o('<!-- vacuum: handheld, 0.34 m long along its x axis (nozzle +x, x in [-0.17, 0.17] about the body origin).')
    w.o('     Bridge handle: capsule 0.035 thick, 0.12 m free span (x in [-0.12, 0]), axis 8 cm above the surface, between')
    w.o(f'     the battery pack and the motor housing. Body origin on the surface at ({f(x)}, {f(y)}, {f(top)}). -->')
    w.open(f'<body name="vacuum" pos="{v(x, y, top)}">')
    w.o('<freejoint name="vacuum_free"/>')
    boxg(w, "vacuum_battery", (-0.17, -0.03, 0), (-0.12, 0.03, 0.09), m_dark, extra=' mass="0.35"')
    w.o('<geom name="vacuum_handle" type="capsule" fromto="-0.145 0 0.08 0.01 0 0.08" size="0.0175" mass="0.1" material="' + m_dark + '" friction="1.2 0.01 0.001"/>')
    boxg(w, "vacuum_housing", (0.0, -0.05, 0), (0.10, 0.05, 0.11), m_body, extra=' mass="0.5"')
    boxg(w, "vacuum_bin", (0.015, -0.052, 0.035), (0.085, 0.052, 0.095), None, "0.75 0.8 0.85 0.6",
         extra=' contype="0" conaffinity="0" mass="0.01"')
    boxg(w, "vacuum_nozzle", (0.10, -0.035, 0), (0.17, 0.035, 0.04), m_accent, extra=' mass="0.08"')
    boxg(w, "vacuum_mouth", (0.165, -0.03, 0.006), (0.1705, 0.03, 0.034), None, "0.02 0.02 0.02 1",
         extra=' contype="0" conaffinity="0" mass="0.001"')
    w.o('<site name="vacuum_tip" pos="0.17 0 0.02" size="0.008" rgba="1 0 0 1"/>')
    w.o('<site name="vacuum_grip" pos="-0.06 0 0.08" size="0.008" rgba="0 1 0 1"/>')
    w.close('</body>')

DEBRIS = [(0.50, -0.27, 0.3), (0.57, -0.30, 1.1), (0.64, -0.26, 2.0), (0.55, -0.21, 0.7), (0.63, -0.18, 2.6)]  # right-front, by the vacuum

def debris(w, top, rgba):
    w.o(f'<!-- debris: flat crumbs on the surface (bottom at z = {f(top)}), no joints, no collisions -->')
    for i, (x, y, a) in enumerate(DEBRIS):
        w.open(f'<body name="debris_{i}" pos="{v(x, y, top + 0.004)}" euler="0 0 {f(a)}">')
        w.o(f'<geom name="debris_{i}_geom" type="box" size="0.02 0.02 0.004" rgba="{rgba}" contype="0" conaffinity="0"/>')
        w.close('</body>')

def visitor(w, env):
    x, y = 2.5, -1.0
    w.o('<!-- visitor: 1.6 m humanoid facing -x (the robot) at visitor_yaw = 0. Joint values are offsets from the start')
    w.o(f'     pose: world x = {f(x)} + visitor_x, world y = {f(y)} + visitor_y, heading = pi + visitor_yaw. Lowest geom 1 cm above the floor. -->')
    w.open(f'<body name="visitor" pos="{v(x, y, 0)}">')
    w.o(f'<joint name="visitor_x" type="slide" axis="1 0 0" range="{v(0.6 - x, 3.2 - x)}" damping="300"/>')
    w.o(f'<joint name="visitor_y" type="slide" axis="0 1 0" range="{v(-2.6 - y, 2.6 - y)}" damping="300"/>')
    w.o('<joint name="visitor_yaw" type="hinge" axis="0 0 1" range="-6.2832 6.2832" damping="40"/>')
    sk, sh, tr, hair, shoe = "0.87 0.68 0.55 1", "0.2 0.45 0.7 1", "0.2 0.2 0.28 1", "0.25 0.16 0.1 1", "0.1 0.1 0.1 1"
    w.o(f'<geom name="visitor_torso" type="capsule" fromto="0 0 0.98 0 0 1.27" size="0.15" mass="28" rgba="{sh}"/>')
    w.o(f'<geom name="visitor_hips" type="capsule" fromto="0 -0.09 0.9 0 0.09 0.9" size="0.11" mass="10" rgba="{tr}"/>')
    w.o(f'<geom name="visitor_neck" type="capsule" fromto="0 0 1.38 0 0 1.43" size="0.045" mass="1" rgba="{sk}"/>')
    w.o(f'<geom name="visitor_head" type="sphere" pos="0 0 1.5" size="0.1" mass="4.5" rgba="{sk}"/>')
    w.o(f'<geom name="visitor_hair" type="ellipsoid" pos="0.015 0 1.545" size="0.098 0.102 0.07" mass="0.1" rgba="{hair}" contype="0" conaffinity="0"/>')
    w.o(f'<geom name="visitor_nose" type="sphere" pos="-0.1 0 1.49" size="0.017" mass="0.01" rgba="{sk}" contype="0" conaffinity="0"/>')
    for s, n in ((1, "l"), (-1, "r")):
        w.o(f'<geom name="visitor_eye_{n}" type="sphere" pos="{v(-0.088, 0.035 * s, 1.52)}" size="0.013" mass="0.01" rgba="0.1 0.1 0.15 1" contype="0" conaffinity="0"/>')
        w.o(f'<geom name="visitor_arm_{n}" type="capsule" fromto="{v(0, 0.2 * s, 1.3, -0.02, 0.235 * s, 0.82)}" size="0.045" mass="3.5" rgba="{sh}"/>')
        w.o(f'<geom name="visitor_hand_{n}" type="sphere" pos="{v(-0.025, 0.24 * s, 0.76)}" size="0.045" mass="0.5" rgba="{sk}"/>')
        w.o(f'<geom name="visitor_leg_{n}" type="capsule" fromto="{v(0, 0.09 * s, 0.86, 0, 0.09 * s, 0.12)}" size="0.065" mass="9" rgba="{tr}"/>')
        w.o(f'<geom name="visitor_foot_{n}" type="box" pos="{v(-0.045, 0.09 * s, 0.04)}" size="0.11 0.045 0.03" mass="1" rgba="{shoe}"/>')
    w.close('</body>')

def actuators(w):
    w.open('<actuator>')
    w.o('<position name="visitor_x" joint="visitor_x" kp="500" ctrlrange="-1.9 0.7"/>')
    w.o('<position name="visitor_y" joint="visitor_y" kp="500" ctrlrange="-1.6 3.6"/>')
    w.o('<position name="visitor_yaw" joint="visitor_yaw" kp="500" ctrlrange="-6.2832 6.2832"/>')
    w.close('</actuator>')

def chair(w, body, cx, cy, yaw, mat, seat_h=0.45):
    """Four-legged chair facing its local +x (backrest on the -x side), turned by `yaw` about z."""
    w.o(f'<!-- {body}: seat {f(seat_h)} m, centre ({f(cx)}, {f(cy)}), facing yaw {f(yaw)} -->')
    w.open(f'<body name="{body}" pos="{v(cx, cy, 0)}" euler="0 0 {f(yaw)}">')
    s = 0.21; lg = 0.035
    boxg(w, f"{body}_seat", (-s, -s, seat_h - 0.04), (s, s, seat_h), mat)
    i = 0
    for dx in (-1, 1):
        for dy in (-1, 1):
            lx = dx * (s - 0.02) - lg / 2; ly = dy * (s - 0.02) - lg / 2
            top = seat_h + 0.45 if dx < 0 else seat_h - 0.04
            boxg(w, f"{body}_leg_{i}", (lx, ly, 0), (lx + lg, ly + lg, top), mat); i += 1
    bx = -(s - 0.02)
    boxg(w, f"{body}_back", (bx - 0.012, -s + 0.01, seat_h + 0.15), (bx + 0.012, s - 0.01, seat_h + 0.43), mat)
    w.close('</body>')

# ----------------------------------------------------------------------------------------
TOP = 0.65          # main surface top (both rooms)

def kitchen():
    env = "kitchen"; w = W()
    header(w, env, None, None, None, None)
    w.open('<asset>')
    w.o('<texture name="kitchen_sky" type="skybox" builtin="gradient" rgb1="0.85 0.9 0.95" rgb2="0.55 0.6 0.7" width="256" height="256"/>')
    w.o('<texture name="kitchen_floor_tex" type="2d" builtin="checker" rgb1="0.86 0.84 0.8" rgb2="0.62 0.6 0.57" width="512" height="512" mark="edge" markrgb="0.5 0.48 0.45"/>')
    w.o('<material name="kitchen_floor_mat" texture="kitchen_floor_tex" texrepeat="3 3" texuniform="true" reflectance="0.05"/>')
    w.o('<material name="kitchen_wall_mat" rgba="0.93 0.9 0.82 1"/>')
    w.o('<material name="kitchen_wood" rgba="0.62 0.44 0.28 1" specular="0.2"/>')
    w.o('<material name="kitchen_wood_dark" rgba="0.42 0.28 0.17 1" specular="0.2"/>')
    w.o('<material name="kitchen_stone" rgba="0.78 0.78 0.76 1" specular="0.4" shininess="0.5"/>')
    w.o('<material name="kitchen_cabinet" rgba="0.88 0.9 0.88 1" specular="0.2"/>')
    w.o('<material name="kitchen_steel" rgba="0.75 0.77 0.8 1" specular="0.6" shininess="0.8"/>')
    w.o('<material name="kitchen_appliance" rgba="0.92 0.93 0.94 1" specular="0.4" shininess="0.5"/>')
    w.o('<material name="kitchen_black" rgba="0.08 0.08 0.09 1" specular="0.3"/>')
    w.o('<material name="kitchen_cup_mat" rgba="0.95 0.95 0.92 1" specular="0.5" shininess="0.6"/>')
    w.o('<material name="kitchen_juice_mat" rgba="0.98 0.6 0.1 1" specular="0.2"/>')
    w.o('<material name="kitchen_vac_body" rgba="0.55 0.2 0.6 1" specular="0.4"/>')
    w.o('<material name="kitchen_vac_dark" rgba="0.15 0.15 0.17 1" specular="0.3"/>')
    w.o('<material name="kitchen_vac_accent" rgba="0.3 0.3 0.33 1" specular="0.3"/>')
    w.close('</asset>')
    w.o('')
    w.open('<worldbody>')
    floor_and_lights(w, env)
    walls(w, env, "kitchen_wall_mat")
    boxg(w, "kitchen_window", (-2.5, -1.3, 1.0), (-2.48, 0.3, 1.9), None, "0.7 0.85 1 1")
    boxg(w, "kitchen_window_frame", (-2.5, -0.53, 1.0), (-2.475, -0.47, 1.9), None, "0.95 0.95 0.95 1")
    cameras(w)
    w.o('')
    # main surface
    surface_table(w, "table", TOP, 0.30, 1.00, -0.60, 0.60, 0.04, "kitchen_wood", "kitchen_wood_dark", label="table (main work surface)")
    w.o('')
    # counter: second surface (a low kitchen island / sideboard with a cabinet base) to the robot's left
    C_TOP = 0.68; cx0, cx1, cy0, cy1 = -0.35, 0.25, 0.55, 1.00
    O = ((cx0 + cx1) / 2, (cy0 + cy1) / 2, C_TOP)
    w.o(f'<!-- counter (put-down surface): top face z = {f(C_TOP)}, x [{f(cx0)}, {f(cx1)}], y [{f(cy0)}, {f(cy1)}]; body origin = centre of the top face -->')
    w.open(f'<body name="counter" pos="{v(*O)}">')
    boxg(w, "counter_top", (cx0, cy0, C_TOP - 0.04), (cx1, cy1, C_TOP), "kitchen_stone", origin=O)
    boxg(w, "counter_cabinet", (cx0 + 0.03, cy0 + 0.04, 0.08), (cx1 - 0.03, cy1 - 0.02, C_TOP - 0.04), "kitchen_cabinet", origin=O)
    boxg(w, "counter_plinth", (cx0 + 0.06, cy0 + 0.08, 0.0), (cx1 - 0.06, cy1 - 0.04, 0.08), "kitchen_black", origin=O)
    boxg(w, "counter_door_gap", (cx0 + 0.03, cy0 + 0.035, 0.12), (cx1 - 0.03, cy0 + 0.04, 0.125), "kitchen_black", origin=O,
         extra=' contype="0" conaffinity="0"')
    w.o(f'<geom name="counter_handle" type="capsule" fromto="{v(-0.12, cy0 + 0.025 - O[1], 0.56 - C_TOP, 0.02, cy0 + 0.025 - O[1], 0.56 - C_TOP)}" size="0.008" material="kitchen_steel"/>')
    w.o(f'<site name="counter_surface" type="box" pos="0 0 0" size="{v((cx1 - cx0) / 2, (cy1 - cy0) / 2, 0.001)}" rgba="0 0 0 0"/>')
    w.close('</body>')
    w.o('')
    cup(w, 0.42, -0.12, TOP, "kitchen_cup_mat")
    juicebox(w, 0.42, 0.15, TOP, "kitchen_juice_mat", "1 1 1 1")
    vacuum(w, 0.57, -0.40, TOP, "kitchen_vac_body", "kitchen_vac_dark", "kitchen_vac_accent")
    debris(w, TOP, "0.55 0.35 0.12 1")
    w.o('')
    # furniture along the left wall (y = +3): fridge, base cabinets with worktop, sink and hob, wall cabinets
    w.o('<!-- fridge: x [-2.4, -1.72], y [2.25, 2.95], 1.85 m -->')
    w.open('<body name="fridge" pos="-2.06 2.6 0">')
    O = (-2.06, 2.6, 0)
    boxg(w, "fridge_body", (-2.4, 2.25, 0), (-1.72, 2.95, 1.85), "kitchen_appliance", origin=O)
    boxg(w, "fridge_gap", (-2.39, 2.245, 1.2), (-1.73, 2.25, 1.21), "kitchen_black", origin=O, extra=' contype="0" conaffinity="0"')
    w.o(f'<geom name="fridge_handle_top" type="capsule" fromto="{v(-1.8 - O[0], 2.22 - O[1], 1.3, -1.8 - O[0], 2.22 - O[1], 1.6)}" size="0.012" material="kitchen_steel"/>')
    w.o(f'<geom name="fridge_handle_bottom" type="capsule" fromto="{v(-1.8 - O[0], 2.22 - O[1], 0.75, -1.8 - O[0], 2.22 - O[1], 1.1)}" size="0.012" material="kitchen_steel"/>')
    boxg(w, "fridge_handle_mount", (-1.81, 2.22, 0.74), (-1.79, 2.25, 1.61), "kitchen_steel", origin=O)
    w.close('</body>')
    w.o('<!-- base cabinets with worktop (top 0.9 m), sink, hob and wall cabinets: x [-1.67, 1.02], y [2.35, 2.95] -->')
    w.open('<body name="kitchen_cabinets" pos="-0.32 2.65 0">')
    O = (-0.32, 2.65, 0)
    boxg(w, "cabinets_base", (-1.65, 2.4, 0.1), (1.0, 2.95, 0.86), "kitchen_cabinet", origin=O)
    boxg(w, "cabinets_plinth", (-1.65, 2.46, 0.0), (1.0, 2.95, 0.1), "kitchen_black", origin=O)
    boxg(w, "cabinets_worktop", (-1.67, 2.35, 0.86), (1.02, 2.95, 0.9), "kitchen_stone", origin=O)
    for i, xd in enumerate((-1.2, -0.6, 0.0, 0.6)):
        w.o(f'<geom name="cabinets_handle_{i}" type="capsule" fromto="{v(xd - 0.08 - O[0], 2.385 - O[1], 0.78, xd + 0.08 - O[0], 2.385 - O[1], 0.78)}" size="0.008" material="kitchen_steel"/>')
        boxg(w, f"cabinets_door_gap_{i}", (xd + 0.295, 2.395, 0.12), (xd + 0.305, 2.4, 0.84), "kitchen_black", origin=O, extra=' contype="0" conaffinity="0"')
    boxg(w, "cabinets_sink", (-0.95, 2.5, 0.895), (-0.45, 2.85, 0.902), "kitchen_steel", origin=O)
    w.o(f'<geom name="cabinets_faucet" type="capsule" fromto="{v(-0.7 - O[0], 2.9 - O[1], 0.9, -0.7 - O[0], 2.9 - O[1], 1.15)}" size="0.015" material="kitchen_steel"/>')
    w.o(f'<geom name="cabinets_spout" type="capsule" fromto="{v(-0.7 - O[0], 2.9 - O[1], 1.15, -0.7 - O[0], 2.75 - O[1], 1.12)}" size="0.012" material="kitchen_steel"/>')
    boxg(w, "cabinets_hob", (0.2, 2.48, 0.9), (0.8, 2.88, 0.91), "kitchen_black", origin=O)
    for i, (hx, hy) in enumerate(((0.35, 2.58), (0.65, 2.58), (0.35, 2.78), (0.65, 2.78))):
        w.o(f'<geom name="cabinets_burner_{i}" type="cylinder" pos="{v(hx - O[0], hy - O[1], 0.911)}" size="0.07 0.002" rgba="0.3 0.3 0.3 1" contype="0" conaffinity="0"/>')
    boxg(w, "cabinets_wall_units", (-1.65, 2.62, 1.45), (1.0, 2.95, 2.1), "kitchen_cabinet", origin=O)
    for i, xd in enumerate((-1.2, -0.6, 0.0, 0.6)):
        w.o(f'<geom name="cabinets_wall_handle_{i}" type="capsule" fromto="{v(xd - O[0], 2.605 - O[1], 1.5, xd - O[0], 2.605 - O[1], 1.65)}" size="0.008" material="kitchen_steel"/>')
    w.close('</body>')
    w.o('')
    chair(w, "chair", -1.7, -0.3, 0.4, "kitchen_wood")
    w.o('')
    w.o('<!-- waste bin in the back-right corner -->')
    w.open('<body name="waste_bin" pos="-1.9 -2.6 0">')
    w.o('<geom name="waste_bin_body" type="cylinder" pos="0 0 0.3" size="0.17 0.3" rgba="0.3 0.5 0.35 1"/>')
    w.o('<geom name="waste_bin_lid" type="cylinder" pos="0 0 0.61" size="0.175 0.01" material="kitchen_steel"/>')
    w.close('</body>')
    w.o('')
    visitor(w, env)
    w.close('</worldbody>')
    w.o('')
    actuators(w)
    w.close('</mujoco>')
    return w.text()

def office():
    env = "office"; w = W()
    header(w, env, None, None, None, None)
    w.open('<asset>')
    w.o('<texture name="office_sky" type="skybox" builtin="gradient" rgb1="0.9 0.92 0.95" rgb2="0.6 0.62 0.68" width="256" height="256"/>')
    w.o('<texture name="office_floor_tex" type="2d" builtin="checker" rgb1="0.5 0.52 0.56" rgb2="0.42 0.44 0.48" width="512" height="512" mark="edge" markrgb="0.38 0.4 0.44"/>')
    w.o('<material name="office_floor_mat" texture="office_floor_tex" texrepeat="2 2" texuniform="true" reflectance="0.02"/>')
    w.o('<material name="office_wall_mat" rgba="0.88 0.9 0.92 1"/>')
    w.o('<material name="office_desk_top" rgba="0.85 0.82 0.74 1" specular="0.2"/>')
    w.o('<material name="office_frame" rgba="0.3 0.31 0.33 1" specular="0.4"/>')
    w.o('<material name="office_shelf" rgba="0.7 0.55 0.38 1" specular="0.2"/>')
    w.o('<material name="office_metal" rgba="0.6 0.62 0.65 1" specular="0.5" shininess="0.6"/>')
    w.o('<material name="office_black" rgba="0.07 0.07 0.08 1" specular="0.4"/>')
    w.o('<material name="office_fabric" rgba="0.15 0.2 0.3 1" specular="0.05"/>')
    w.o('<material name="office_cup_mat" rgba="0.2 0.45 0.75 1" specular="0.5" shininess="0.6"/>')
    w.o('<material name="office_juice_mat" rgba="0.35 0.7 0.25 1" specular="0.2"/>')
    w.o('<material name="office_vac_body" rgba="0.85 0.3 0.15 1" specular="0.4"/>')
    w.o('<material name="office_vac_dark" rgba="0.15 0.15 0.17 1" specular="0.3"/>')
    w.o('<material name="office_vac_accent" rgba="0.3 0.3 0.33 1" specular="0.3"/>')
    w.close('</asset>')
    w.o('')
    w.open('<worldbody>')
    floor_and_lights(w, env)
    walls(w, env, "office_wall_mat")
    boxg(w, "office_whiteboard", (3.48, -1.0, 0.9), (3.5, 1.0, 2.0), None, "0.97 0.97 0.97 1")
    boxg(w, "office_whiteboard_tray", (3.44, -1.0, 0.88), (3.5, 1.0, 0.9), "office_metal")
    boxg(w, "office_window", (-1.2, 2.98, 1.0), (1.2, 3.0, 1.9), None, "0.7 0.85 1 1")
    cameras(w)
    w.o('')
    # desk: main surface with panel legs and a modesty panel; monitor at the back left
    x0, x1, y0, y1 = 0.30, 1.05, -0.65, 0.65; O = ((x0 + x1) / 2, 0.0, TOP)
    w.o(f'<!-- desk (main work surface): top face z = {f(TOP)}, x [{f(x0)}, {f(x1)}], y [{f(y0)}, {f(y1)}]; body origin = centre of the top face.')
    w.o('     Monitor at the back left (x >= 0.89, y [0.07, 0.63]). -->')
    w.open(f'<body name="desk" pos="{v(*O)}">')
    boxg(w, "desk_top", (x0, y0, TOP - 0.03), (x1, y1, TOP), "office_desk_top", origin=O)
    boxg(w, "desk_panel_left", (x0 + 0.04, y1 - 0.06, 0), (x1 - 0.03, y1 - 0.03, TOP - 0.03), "office_frame", origin=O)
    boxg(w, "desk_panel_right", (x0 + 0.04, y0 + 0.03, 0), (x1 - 0.03, y0 + 0.06, TOP - 0.03), "office_frame", origin=O)
    boxg(w, "desk_modesty_panel", (x1 - 0.06, y0 + 0.06, 0.3), (x1 - 0.04, y1 - 0.06, TOP - 0.03), "office_frame", origin=O)
    boxg(w, "desk_monitor_base", (0.89, 0.27, TOP), (1.01, 0.43, TOP + 0.01), "office_black", origin=O)
    boxg(w, "desk_monitor_neck", (0.95, 0.33, TOP + 0.01), (0.97, 0.37, TOP + 0.2), "office_black", origin=O)
    boxg(w, "desk_monitor_screen", (0.92, 0.07, TOP + 0.17), (0.95, 0.63, TOP + 0.5), "office_black", origin=O)
    boxg(w, "desk_monitor_display", (0.919, 0.085, TOP + 0.185), (0.92, 0.615, TOP + 0.485), None, "0.2 0.3 0.45 1",
         origin=O, extra=' contype="0" conaffinity="0"')
    w.o(f'<site name="desk_surface" type="box" pos="0 0 0" size="{v((x1 - x0) / 2, (y1 - y0) / 2, 0.001)}" rgba="0 0 0 0"/>')
    w.close('</body>')
    w.o('')
    surface_table(w, "side_table", 0.64, -0.25, 0.25, 0.55, 1.00, 0.025, "office_shelf", "office_frame", leg=0.04, inset=0.02,
                  apron=True, label="side_table (put-down surface)")
    w.o('')
    cup(w, 0.42, -0.12, TOP, "office_cup_mat")
    juicebox(w, 0.42, 0.15, TOP, "office_juice_mat", "1 1 1 1")
    vacuum(w, 0.57, -0.40, TOP, "office_vac_body", "office_vac_dark", "office_vac_accent")
    debris(w, TOP, "0.95 0.85 0.1 1")
    w.o('')
    # bookshelf against the right wall (y = -3)
    bx0, bx1, by0, by1, bh = -1.7, -0.7, -2.95, -2.63, 1.9
    O = ((bx0 + bx1) / 2, (by0 + by1) / 2, 0)
    w.o(f'<!-- bookshelf: x [{f(bx0)}, {f(bx1)}], y [{f(by0)}, {f(by1)}], {f(bh)} m, against the right wall -->')
    w.open(f'<body name="bookshelf" pos="{v(*O)}">')
    boxg(w, "bookshelf_side_0", (bx0, by0, 0), (bx0 + 0.02, by1, bh), "office_shelf", origin=O)
    boxg(w, "bookshelf_side_1", (bx1 - 0.02, by0, 0), (bx1, by1, bh), "office_shelf", origin=O)
    boxg(w, "bookshelf_back", (bx0 + 0.02, by0, 0), (bx1 - 0.02, by0 + 0.01, bh), "office_shelf", origin=O)
    shelves = [0.0, 0.45, 0.9, 1.35, 1.88]
    for i, z in enumerate(shelves):
        boxg(w, f"bookshelf_board_{i}", (bx0 + 0.02, by0 + 0.01, z), (bx1 - 0.02, by1, z + 0.02), "office_shelf", origin=O)
    colors = ["0.6 0.1 0.1 1", "0.1 0.3 0.6 1", "0.2 0.5 0.2 1", "0.8 0.7 0.2 1", "0.4 0.2 0.5 1", "0.9 0.9 0.85 1", "0.2 0.2 0.2 1"]
    k = 0
    for i, z in enumerate(shelves[:4]):
        x = bx0 + 0.05
        j = 0
        while x < bx1 - 0.12:
            th = 0.025 + 0.012 * ((k * 7) % 4); hgt = 0.22 + 0.03 * ((k * 5) % 5); dep = 0.17 + 0.02 * ((k * 3) % 3)
            if i == 1 and j == 6:
                x += 0.25  # a gap on the second shelf
            if x + th > bx1 - 0.03:
                break
            boxg(w, f"bookshelf_book_{k}", (x, by0 + 0.02, z + 0.02), (x + th, by0 + 0.02 + dep, z + 0.02 + hgt), None,
                 colors[k % len(colors)], origin=O)
            x += th + 0.003; k += 1; j += 1
    w.close('</body>')
    w.o('')
    # filing cabinet against the left wall
    fx0, fx1, fy0, fy1, fh = -1.9, -1.43, 2.35, 2.95, 1.02
    O = ((fx0 + fx1) / 2, (fy0 + fy1) / 2, 0)
    w.o(f'<!-- filing_cabinet: x [{f(fx0)}, {f(fx1)}], y [{f(fy0)}, {f(fy1)}], {f(fh)} m, three drawers facing -y -->')
    w.open(f'<body name="filing_cabinet" pos="{v(*O)}">')
    boxg(w, "filing_cabinet_body", (fx0, fy0, 0), (fx1, fy1, fh), "office_metal", origin=O)
    for i in range(3):
        z0 = 0.05 + i * 0.32
        boxg(w, f"filing_cabinet_drawer_{i}", (fx0 + 0.02, fy0 - 0.01, z0), (fx1 - 0.02, fy0, z0 + 0.29), "office_metal", origin=O)
        boxg(w, f"filing_cabinet_handle_{i}", (O[0] - 0.07, fy0 - 0.03, z0 + 0.2), (O[0] + 0.07, fy0 - 0.01, z0 + 0.22), "office_black", origin=O)
        boxg(w, f"filing_cabinet_label_{i}", (O[0] - 0.04, fy0 - 0.012, z0 + 0.235), (O[0] + 0.04, fy0 - 0.01, z0 + 0.265), None,
             "0.95 0.95 0.9 1", origin=O, extra=' contype="0" conaffinity="0"')
    w.close('</body>')
    w.o('')
    # office chair (swivel chair on a five-star base with casters), behind-right of the robot, facing +x
    cx, cy = -1.6, -0.2
    w.o(f'<!-- office_chair: five-star base (radius 0.3) centred at ({f(cx)}, {f(cy)}), seat 0.47 m, facing +x -->')
    w.open(f'<body name="office_chair" pos="{v(cx, cy, 0)}">')
    for i in range(5):
        a = 2 * math.pi * i / 5 + 0.3
        ex, ey = 0.28 * math.cos(a), 0.28 * math.sin(a)
        w.o(f'<geom name="office_chair_spoke_{i}" type="capsule" fromto="{v(0, 0, 0.075, ex, ey, 0.065)}" size="0.018" material="office_black"/>')
        w.o(f'<geom name="office_chair_caster_{i}" type="sphere" pos="{v(ex, ey, 0.025)}" size="0.025" material="office_black"/>')
        w.o(f'<geom name="office_chair_caster_post_{i}" type="cylinder" fromto="{v(ex, ey, 0.04, ex, ey, 0.065)}" size="0.008" material="office_metal"/>')
    w.o('<geom name="office_chair_column" type="cylinder" fromto="0 0 0.07 0 0 0.43" size="0.028" material="office_metal"/>')
    w.o('<geom name="office_chair_seat" type="box" pos="0 0 0.45" size="0.24 0.24 0.04" material="office_fabric"/>')
    w.o('<geom name="office_chair_back_post" type="box" pos="-0.25 0 0.6" size="0.015 0.03 0.15" material="office_black"/>')
    w.o('<geom name="office_chair_back" type="box" pos="-0.26 0 0.86" size="0.03 0.22 0.22" euler="0 -0.12 0" material="office_fabric"/>')
    for s in (1, -1):
        w.o(f'<geom name="office_chair_armrest_{"l" if s > 0 else "r"}" type="box" pos="{v(0, 0.24 * s, 0.66)}" size="0.16 0.025 0.015" material="office_black"/>')
        w.o(f'<geom name="office_chair_armpost_{"l" if s > 0 else "r"}" type="box" pos="{v(-0.05, 0.24 * s, 0.56)}" size="0.015 0.015 0.09" material="office_black"/>')
    w.close('</body>')
    w.o('')
    w.o('<!-- potted plant in the back-right corner -->')
    w.open('<body name="plant" pos="-2.15 -2.6 0">')
    w.o('<geom name="plant_pot" type="cylinder" pos="0 0 0.2" size="0.16 0.2" rgba="0.75 0.4 0.25 1"/>')
    w.o('<geom name="plant_stem" type="capsule" fromto="0 0 0.35 0 0 0.8" size="0.02" rgba="0.35 0.25 0.12 1"/>')
    w.o('<geom name="plant_foliage" type="ellipsoid" pos="0 0 1.0" size="0.3 0.3 0.35" rgba="0.2 0.5 0.2 1"/>')
    w.close('</body>')
    w.o('')
    visitor(w, env)
    w.close('</worldbody>')
    w.o('')
    actuators(w)
    w.close('</mujoco>')
    return w.text()

if __name__ == "__main__":
    import os
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "..", "models", "environments")
    for name, fn in (("kitchen", kitchen), ("office", office)):
        os.makedirs(f"{out}/{name}", exist_ok=True)
        with open(f"{out}/{name}/{name}.xml", "w") as fh:
            fh.write(fn())
    print("written")

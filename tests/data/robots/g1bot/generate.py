#!/usr/bin/env python3
"""g1bot: a humanoid with the Unitree G1's published kinematics (29-DOF version with Dex3-1
hands: the joint origins, axes and limits of the MJCF model of it in MuJoCo Menagerie), for the
Task Matrix harness's tests (a robot the programs were not written for). Joint numbers are
written below; collision shapes are primitives sized after the robot's links; the floating base
is a planar base and the legs are fixed straight. Writes g1bot.xml next to this file. Plain
Python."""
import os, re

HERE = os.path.dirname(os.path.abspath(__file__))

def side(s):
    L = s == "left"
    m = 1 if L else -1          # y mirror
    p = s  # name prefix
    rollr = "-1.5882 2.2515" if L else "-2.2515 1.5882"
    th1 = "-0.724312 1.0472" if L else "-1.0472 0.724312"
    th2 = "0 1.74533" if L else "-1.74533 0"
    f0 = "-1.5708 0" if L else "0 1.5708"
    f1 = "-1.74533 0" if L else "0 1.74533"
    qx = 0.139201 * m
    palm_y = -0.04 * m
    def finger(name, z):
        return f"""
                          <body name="{p}_hand_{name}_0_link" pos="0.1192 {0.0046*m:.4f} {z}">
                            <inertial pos="0.0354744 0 0" mass="0.0588507" diaginertia="1.3e-05 1.2e-05 6e-06"/>
                            <joint name="{p}_hand_{name}_0_joint" class="g1_finger" axis="0 0 1" range="{f0}"/>
                            <geom name="{p}_{name}_0" class="g1_finger" fromto="0.008 0 0 0.0458 0 0" size="0.0095"/>
                            <body name="{p}_hand_{name}_1_link" pos="0.0458 0 0">
                              <inertial pos="0.0262819 0 0" mass="0.0203063" diaginertia="4.6e-06 3.9e-06 1.5e-06"/>
                              <joint name="{p}_hand_{name}_1_joint" class="g1_finger" axis="0 0 1" range="{f1}"/>
                              <geom name="{p}_{name}_1" class="g1_finger" fromto="0.008 0 0 0.040 0 0" size="0.0085"/>
                            </body>
                          </body>"""
    return f"""
            <body name="{p}_shoulder_pitch_link" pos="0.0039563 {0.10022*m:.5f} 0.24778" quat="0.990264 {qx:.6f} 0 0">
              <inertial pos="0 {0.035892*m:.6f} -0.011628" mass="0.718" diaginertia="4.7e-04 4.3e-04 4.1e-04"/>
              <joint name="{p}_shoulder_pitch_joint" class="g1_shoulder" axis="0 1 0" range="-3.0892 2.6704"/>
              <geom name="{p}_shoulder" class="g1_dark" type="cylinder" size="0.03 0.025" pos="0 {0.04*m} -0.01" quat="0.707107 0 0.707107 0"/>
              <body name="{p}_shoulder_roll_link" pos="0 {0.038*m} -0.013831" quat="0.990268 {-0.139172*m:.6f} 0 0">
                <inertial pos="0 {0.00727*m:.5f} -0.063243" mass="0.643" diaginertia="6.9e-04 6.2e-04 3.9e-04"/>
                <joint name="{p}_shoulder_roll_joint" class="g1_shoulder" axis="1 0 0" range="{rollr}"/>
                <geom name="{p}_shoulder_roll" type="cylinder" size="0.03 0.015" pos="-0.004 {0.006*m} -0.053"/>
                <body name="{p}_shoulder_yaw_link" pos="0 {0.00624*m} -0.1032">
                  <inertial pos="0.010773 0 -0.072009" mass="0.734" diaginertia="1.1e-03 1.0e-03 4.0e-04"/>
                  <joint name="{p}_shoulder_yaw_joint" class="g1_shoulder" axis="0 0 1" range="-2.618 2.618"/>
                  <geom name="{p}_upper_arm" fromto="0.004 0 -0.012 0.012 0 -0.066" size="0.031"/>
                  <body name="{p}_elbow_link" pos="0.015783 0 -0.080518">
                    <inertial pos="0.064956 0 -0.010062" mass="0.6" diaginertia="4.4e-04 4.2e-04 2.6e-04"/>
                    <joint name="{p}_elbow_joint" class="g1_elbow" axis="0 1 0" range="-1.0472 2.0944"/>
                    <geom name="{p}_elbow" class="g1_dark" type="sphere" size="0.03"/>
                    <geom name="{p}_forearm" fromto="0.032 0 -0.003 0.086 0 -0.009" size="0.027"/>
                    <body name="{p}_wrist_roll_link" pos="0.1 {0.00188791*m:.6f} -0.01">
                      <inertial pos="0.0171394 0 0" mass="0.085445" diaginertia="5.5e-05 5.0e-05 3.6e-05"/>
                      <joint name="{p}_wrist_roll_joint" class="g1_wrist" axis="1 0 0" range="-1.97222 1.97222"/>
                      <geom name="{p}_wrist_roll" class="g1_dark" fromto="0.004 0 0 0.026 0 0" size="0.025"/>
                      <body name="{p}_wrist_pitch_link" pos="0.038 0 0">
                        <inertial pos="0.0229999 0 0" mass="0.48405" diaginertia="4.3e-04 4.3e-04 1.6e-04"/>
                        <joint name="{p}_wrist_pitch_joint" class="g1_wrist" axis="0 1 0" range="-1.61443 1.61443"/>
                        <geom name="{p}_wrist_pitch" fromto="0.002 0 0 0.03 0 0" size="0.026"/>
                        <body name="{p}_wrist_yaw_link" pos="0.046 0 0">
                          <inertial pos="0.0885506 0 0" mass="0.457415" diaginertia="1.1e-03 9.0e-04 3.2e-04"/>
                          <joint name="{p}_wrist_yaw_joint" class="g1_wrist" axis="0 0 1" range="-1.61443 1.61443"/>
                          <geom name="{p}_palm" class="g1_hand" type="box" pos="0.0775 {0.008*m:.4f} 0" size="0.0335 0.014 0.043"/>
                          <site name="{p}_palm" pos="0.115 {palm_y:.3f} 0"/>
                          <body name="{p}_hand_thumb_0_link" pos="0.067 {0.003*m:.4f} 0">
                            <inertial pos="0 {-0.0086*m:.4f} 0" mass="0.0862366" diaginertia="1.7e-05 1.6e-05 1.4e-05"/>
                            <joint name="{p}_hand_thumb_0_joint" class="g1_finger" axis="0 1 0" range="-1.0472 1.0472"/>
                            <body name="{p}_hand_thumb_1_link" pos="-0.0025 {-0.0193*m:.4f} 0">
                              <inertial pos="0 {-0.0354744*m:.6f} 0" mass="0.0588507" diaginertia="1.3e-05 1.2e-05 6e-06"/>
                              <joint name="{p}_hand_thumb_1_joint" class="g1_finger" axis="0 0 1" range="{th1}"/>
                              <geom name="{p}_thumb_1" class="g1_finger" type="box" size="0.01 0.013 0.01" pos="-0.001 {-0.032*m} 0"/>
                              <body name="{p}_hand_thumb_2_link" pos="0 {-0.0458*m} 0">
                                <inertial pos="0 {-0.0262819*m:.6f} 0" mass="0.0203063" diaginertia="4.6e-06 3.9e-06 1.5e-06"/>
                                <joint name="{p}_hand_thumb_2_joint" class="g1_finger" axis="0 0 1" range="{th2}"/>
                                <geom name="{p}_thumb_2" class="g1_finger" fromto="0 {-0.008*m} 0 0 {-0.040*m} 0" size="0.0085"/>
                              </body>
                            </body>
                          </body>{finger("middle", -0.0285)}{finger("index", 0.0285)}
                        </body>
                      </body>
                    </body>
                  </body>
                </body>
              </body>
            </body>"""

def leg(m):
    y = 0.117 * m
    return f"""
      <geom name="{'l' if m > 0 else 'r'}_thigh" fromto="0.012 {y:.3f} -0.15 -0.048 {y:.3f} -0.40" size="0.055"/>
      <geom name="{'l' if m > 0 else 'r'}_knee" class="g1_dark" type="sphere" pos="-0.053 {y:.3f} -0.445" size="0.05"/>
      <geom name="{'l' if m > 0 else 'r'}_shin" fromto="-0.053 {y:.3f} -0.49 -0.053 {y:.3f} -0.71" size="0.042"/>
      <geom name="{'l' if m > 0 else 'r'}_foot" class="g1_dark" type="box" pos="-0.005 {y:.3f} -0.765" size="0.11 0.038 0.024"/>"""

# Every joint gets a position actuator of its class, over its range.
def cls(j):
    if j.startswith("base"): return "g1_base"
    if j.startswith("waist"): return "g1_torso"
    if "hand" in j: return "g1_finger"
    if "elbow" in j: return "g1_elbow"
    if "wrist" in j: return "g1_wrist"
    return "g1_shoulder"
xml = f"""<mujoco model="g1bot">
  <!-- g1bot: Unitree G1 (29-DOF, Dex3-1 hands) kinematics from MuJoCo Menagerie's
       unitree_g1/g1_with_hands.xml: planar base, legs fixed straight, 3-DOF waist (yaw, roll,
       pitch), no neck (the head and its camera are fixed to the torso), two 7-DOF arms, hands with
       a 3-joint thumb and two 2-joint fingers. Written by generate.py. At qpos0 the upper arms
       hang and the forearms point forward (+x); palm sites: +x along the fingers, the palm faces
       -y (left) / +y (right). -->
  <compiler angle="radian" autolimits="true"/>
  <option timestep="0.002"/>
  <default>
    <default class="g1bot">
      <geom type="capsule" density="1000" rgba="0.72 0.73 0.75 1" friction="1 0.01 0.001"/>
      <joint damping="10" armature="0.05"/>
      <position kp="400"/>
      <site group="4" rgba="1 0.3 0.3 0.6"/>
      <default class="g1_dark"><geom rgba="0.16 0.16 0.18 1"/></default>
      <default class="g1_hand"><geom rgba="0.22 0.22 0.24 1"/></default>
      <default class="g1_visual"><geom contype="0" conaffinity="0" density="0" rgba="0.05 0.05 0.06 1"/></default>
      <default class="g1_base"><joint damping="600" armature="1"/><position kp="2000"/></default>
      <default class="g1_torso"><joint damping="150" armature="0.5"/><position kp="2000"/></default>
      <default class="g1_shoulder"><joint damping="20" armature="0.1"/><position kp="400"/></default>
      <default class="g1_elbow"><joint damping="10" armature="0.05"/><position kp="300"/></default>
      <default class="g1_wrist"><joint damping="4" armature="0.03"/><position kp="150"/></default>
      <default class="g1_finger">
        <joint damping="0.5" armature="0.005"/><position kp="30"/>
        <geom rgba="0.25 0.25 0.27 1" friction="1.5 0.02 0.002"/>
      </default>
    </default>
  </default>
  <worldbody>
    <body name="pelvis" childclass="g1bot" pos="0 0 0.793">
      <joint name="base_x" class="g1_base" type="slide" axis="1 0 0" range="-5 5"/>
      <joint name="base_y" class="g1_base" type="slide" axis="0 1 0" range="-5 5"/>
      <joint name="base_yaw" class="g1_base" type="hinge" axis="0 0 1" range="-3.14159 3.14159"/>
      <geom name="pelvis" class="g1_dark" type="box" pos="0 0 -0.07" size="0.06 0.1 0.055"/>{leg(1)}{leg(-1)}
      <body name="waist_yaw_link">
        <inertial pos="0 0 0.018" mass="0.214" diaginertia="1.6e-04 1.1e-04 1.0e-04"/>
        <joint name="waist_yaw_joint" class="g1_torso" axis="0 0 1" range="-2.618 2.618"/>
        <body name="waist_roll_link" pos="-0.0039635 0 0.044">
          <inertial pos="0 0 0" mass="0.086" diaginertia="8e-06 7e-06 6e-06"/>
          <joint name="waist_roll_joint" class="g1_torso" axis="1 0 0" range="-0.52 0.52"/>
          <body name="torso_link">
            <inertial pos="0.002 0 0.184568" mass="7.818" diaginertia="0.12 0.11 0.027"/>
            <joint name="waist_pitch_joint" class="g1_torso" axis="0 1 0" range="-0.52 0.52"/>
            <geom name="waist" class="g1_dark" fromto="0 -0.06 0.03 0 0.06 0.03" size="0.05"/>
            <geom name="chest" type="box" pos="0 0 0.19" size="0.07 0.085 0.11"/>
            <geom name="neck" class="g1_dark" fromto="0 0 0.31 0 0 0.35" size="0.035"/>
            <geom name="head" class="g1_dark" type="ellipsoid" pos="0.005 0 0.405" size="0.065 0.06 0.075"/>
            <camera name="head_cam" pos="0.068 0 0.41" xyaxes="0 -1 0 0.644218 0 0.764842" fovy="58"/>
{side("left")}{side("right")}
          </body>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator>
ACTUATORS
  </actuator>
</mujoco>
"""
acts = "\n".join(f'    <position name="{j}" class="{cls(j)}" joint="{j}" ctrlrange="{r}"/>'
                 for j, r in re.findall(r'<joint name="([^"]+)"[^>]*range="([^"]+)"', xml))
with open(os.path.join(HERE, "g1bot.xml"), "w") as out:
    out.write(xml.replace("ACTUATORS", acts))

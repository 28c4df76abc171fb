#!/usr/bin/env python3
"""Reference odometry for kurt_driver_test.cpp, worked out from the formulas documented in
shared research notes (kurt.md section 1.7, the real driver's per-frame odometry), independently
of the C++ code. Prints x, y, yaw, linear, angular after each frame as exact hex doubles."""
import math

PERIMETER, AXIS, TA, TICKS, DT, EPS = 0.379, 0.28, 0.69, 21950, 0.01, 0.0001
FRAMES = [(100, 100)] * 5 + [(150, -150)] * 3 + [(-200, -180)] * 4 + [(300, 250)] * 6 + \
         [(0, 0), (-32768, 32767), (1, 0)]

x = z = th = 0.0
for left_ticks, right_ticks in FRAMES:
    l = PERIMETER * left_ticks / TICKS           # distance per side
    r = PERIMETER * right_ticks / TICKS
    vl, vr = l / DT, r / DT                      # speeds with the fixed 10 ms
    linear = (vl + vr) / 2
    angular = (vr - vl) / AXIS * TA
    sx = sz = dth = 0.0                          # step in the internal frame (z ahead, th cw)
    if abs(l - r) < EPS:
        if abs(l) >= EPS:
            sz = (l + r) / 2
    else:
        dist = (l + r) / 2
        dth = (l - r) / AXIS * TA
        sx, sz = dist * math.sin(dth), dist * math.cos(dth)
    x += sx * math.cos(th) + sz * math.sin(th)
    z += -sx * math.sin(th) + sz * math.cos(th)
    th += dth
    if th > math.pi:
        th -= 2 * math.pi
    if th < -math.pi:
        th += 2 * math.pi
    print(left_ticks, right_ticks, (z).hex(), (-x).hex(), (-th).hex(), linear.hex(), angular.hex())

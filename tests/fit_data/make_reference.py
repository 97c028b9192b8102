"""Regenerates cylinder_arc30_short.csv and prints its least-squares
cylinder at 40 digits (mpmath), for tests/fit_reference.rs.

Independent of cmm: Gauss-Newton with finite-difference Jacobian (step 1e-25)
on the parameters (x0, y0, theta, phi, r), axis through (x0, y0, 0) along
(sin t cos p, sin t sin p, cos t). Run: python3 make_reference.py
"""
import math
import random

import mpmath as mp

mp.mp.dps = 40
rnd = random.Random(7)


def unit(th, ph):
    return [mp.sin(th) * mp.cos(ph), mp.sin(th) * mp.sin(ph), mp.cos(th)]


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def norm(a):
    return mp.sqrt(dot(a, a))


def frame(d):
    h = [1, 0, 0] if abs(d[0]) < 0.6 else [0, 1, 0]
    e1 = cross(h, d)
    n = norm(e1)
    e1 = [c / n for c in e1]
    return e1, cross(d, e1)


def gauss_newton(res, x, iters=60):
    x = mp.matrix(x)
    for _ in range(iters):
        r = res(x)
        jac = mp.matrix(len(r), len(x))
        h = mp.mpf(10) ** -25
        for j in range(len(x)):
            xp = x.copy()
            xp[j] += h
            rp = res(xp)
            for i in range(len(r)):
                jac[i, j] = (rp[i] - r[i]) / h
        dx = mp.lu_solve(jac.T * jac, -(jac.T * mp.matrix(r)))
        x = x + dx
        if mp.norm(dx) < mp.mpf(10) ** -35:
            break
    return x


rnd.seed(100)
th, ph = rnd.uniform(0.2, 2.9), rnd.uniform(-3, 3)
d0 = unit(mp.mpf(th), mp.mpf(ph))
e1, e2 = frame(d0)
a0 = [rnd.uniform(-200, 200) for _ in range(3)]
R = rnd.uniform(2, 80)
span = math.radians(rnd.choice([30, 45, 90, 180, 360]))
L = R * rnd.choice([0.1, 0.3, 1, 3])
pts = []
for i in range(40):
    t, z, r = rnd.uniform(0, span), rnd.uniform(0, L), R + rnd.gauss(0, 0.002)
    pts.append([float(a0[k] + r * mp.cos(t) * e1[k] + r * mp.sin(t) * e2[k] + z * d0[k]) for k in range(3)])
with open("cylinder_arc30_short.csv", "w") as f:
    f.write("x,y,z\n")
    for p in pts:
        f.write("%s,%s,%s\n" % tuple(repr(c) for c in p))
P = [[mp.mpf(c) for c in p] for p in pts]


def residuals(x):
    d, a = unit(x[2], x[3]), [x[0], x[1], mp.mpf(0)]
    return [norm(cross(sub(p, a), d)) - x[4] for p in P]


t0 = -mp.mpf(a0[2]) / d0[2]
x = gauss_newton(residuals, [a0[0] + t0 * d0[0], a0[1] + t0 * d0[1], mp.mpf(th), mp.mpf(ph), R])
print("axis point (z = 0):", mp.nstr(x[0], 25), mp.nstr(x[1], 25))
print("direction:", *[mp.nstr(v, 25) for v in unit(x[2], x[3])])
print("radius:", mp.nstr(x[4], 25))

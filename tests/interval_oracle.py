"""Oracles: interval boxes as array code, for the tests to compare the compiled kernels with.

The region proof evaluates the Newton-Euler regressor recursion over boxes of joint positions
in compiled kernels: midpoint-radius balls (``certify/ball_kernels.py``) and interval boxes
(``certify/box_kernels.py``). The interval-box arithmetic here is the array formulation the
box kernels were written from, operation for operation (Moore, Kearfott & Cloud,
*Introduction to Interval Analysis*, SIAM 2009, Ch. 2-4): an interval array is a pair
``(lo, hi)``, vectors carry their three components on the last axis, every operation returns
an enclosure widened outward for floating-point rounding (a sum or product by one ulp, a
product by a point matrix by 16 units of round-off of the terms' magnitudes, a cosine or sine
by 4e-16 plus 4 ulps of the angle). :class:`Box` is the algebra that
``regressor_bounds._column_groups`` runs the recursion in (the kernels' oracle, equal to them
bit for bit); :func:`inertia_arrays` the array code of the inertia matrix's enclosure, in
either algebra (the ball kernel's oracle); :func:`inertia_box` the whole enclosure of D in
interval boxes, armature and symmetry included, as ``inertia_enclosure`` finishes it.
"""

import numpy as np

from gd_analyze.certify import intervals as iv
from gd_analyze.certify import regressor_bounds as rb

_out = iv._out


def point(x):
    """The degenerate interval [x, x]."""
    x = np.asarray(x, float)
    return x, x


def sub(a, b):
    """a - b, rounded outward."""
    return _out(a[0] - b[1], a[1] - b[0])


def mul(a, b):
    """a b, rounded outward (the four endpoint products)."""
    p = (a[0] * b[0], a[0] * b[1], a[1] * b[0], a[1] * b[1])
    return _out(np.minimum(np.minimum(p[0], p[1]), np.minimum(p[2], p[3])),
                np.maximum(np.maximum(p[0], p[1]), np.maximum(p[2], p[3])))


def cos_sin(lo, hi):
    """Enclosures of cos and sin over [lo, hi]."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)

    def enclose(a, b):
        ca, cb = np.cos(a), np.cos(b)
        top = np.maximum(ca, cb)
        bot = np.minimum(ca, cb)
        # a multiple of 2 pi inside: cos reaches 1; an odd multiple of pi: -1
        k_hi = np.ceil(a / (2 * np.pi) - 1e-12)
        has_max = k_hi * 2 * np.pi <= b + 1e-12
        k_lo = np.ceil((a - np.pi) / (2 * np.pi) - 1e-12)
        has_min = k_lo * 2 * np.pi + np.pi <= b + 1e-12
        wide = (b - a) >= 2 * np.pi
        top = np.where(has_max | wide, 1.0, top)
        bot = np.where(has_min | wide, -1.0, bot)
        slack = 4e-16 + 4 * np.finfo(float).eps * np.maximum(np.abs(a), np.abs(b))
        return np.maximum(bot - slack, -1.0), np.minimum(top + slack, 1.0)
    return enclose(lo, hi), enclose(lo - np.pi / 2, hi - np.pi / 2)


def cross(a, b):
    """The cross product a x b of interval vectors."""
    def comp(x):
        return a[0][..., x], a[1][..., x]

    def compb(x):
        return b[0][..., x], b[1][..., x]
    parts = [sub(mul(comp(i), compb(j)), mul(comp(j), compb(i)))
             for i, j in ((1, 2), (2, 0), (0, 1))]
    return np.stack([p[0] for p in parts], -1), np.stack([p[1] for p in parts], -1)


def matvec(M, v):
    """M v for a point matrix M and an interval vector v, rounded outward."""
    M = np.asarray(M, float)
    Mp, Mn = np.maximum(M, 0.0), np.minimum(M, 0.0)
    lo = v[0] @ Mp.T + v[1] @ Mn.T
    hi = v[1] @ Mp.T + v[0] @ Mn.T
    slack = 16 * iv.ROUNDING * (iv.magnitude(v) @ np.abs(M).T)
    return lo - slack, hi + slack


class Box:
    """Interval boxes: a vector is (lo, hi), each (..., 3)."""

    add, scale, cross = staticmethod(iv.add), staticmethod(iv.scale), staticmethod(cross)
    matvec, point = staticmethod(matvec), staticmethod(point)

    @staticmethod
    def zeros(shape):
        z = np.zeros(tuple(shape) + (3,))
        return z, z.copy()

    @staticmethod
    def unit_z(a, index):
        a[0][:, index, 2] += 1.0
        a[1][:, index, 2] += 1.0

    @staticmethod
    def put_point(a, index, value):
        a[0][:, index] = value
        a[1][:, index] = value

    @staticmethod
    def sym(a, ab):
        """E x for the symmetric unit matrix E of the index pair ab (||E||_2 = 1)."""
        return tuple(rb._sym(x, ab) for x in a)

    @staticmethod
    def z(a):
        return a[0][..., 2], a[1][..., 2]

    def __init__(self, q_lo, q_hi):
        self.cs = cos_sin(q_lo, q_hi)
        self.q = (q_lo, q_hi)

    def rotz(self, k, v, transpose):
        (clo, chi), (slo, shi) = self.cs
        return rotz((clo[:, k], chi[:, k]), (slo[:, k], shi[:, k]), v, transpose)

    def slide(self, k, t, dz):
        ql, qh = self.q[0][:, k, None, None], self.q[1][:, k, None, None]
        base = np.broadcast_to(t, ql.shape[:1] + (1, 3))
        return iv.add((base, base), (np.minimum(ql * dz, qh * dz), np.maximum(ql * dz, qh * dz)))

    def fixed(self, t, B):
        base = np.broadcast_to(t, (B, 1, 3))
        return base, base


def rotz(c, s, v, transpose):
    """Rz(q) v or Rz(q)^T v for interval cos c and sin s of shape (B,), v (B, C, 3)."""
    cb = (c[0][:, None], c[1][:, None])
    sb = (s[0][:, None], s[1][:, None])
    x, y = (v[0][..., 0], v[1][..., 0]), (v[0][..., 1], v[1][..., 1])
    if transpose:
        nx = iv.add(mul(cb, x), mul(sb, y))
        ny = sub(mul(cb, y), mul(sb, x))
    else:
        nx = sub(mul(cb, x), mul(sb, y))
        ny = iv.add(mul(sb, x), mul(cb, y))
    return (np.stack([nx[0], ny[0], v[0][..., 2]], -1),
            np.stack([nx[1], ny[1], v[1][..., 2]], -1))


def inertial_forward(chain):
    """Per link k: wd, vd (B, n, 3) of the inertial channels (qd = 0, qdd = e_j, g = 0)."""
    A, n, B = chain.A, chain.robot.n, chain.B
    wd, vd = A.zeros((B, n)), A.zeros((B, n))
    out = []
    for k in range(n):
        a = A.add(vd, A.cross(wd, chain.p(k)))
        vd, wd = chain.rot_t(k, a), chain.rot_t(k, wd)
        A.unit_z(vd if chain.pris[k] else wd, k)
        out.append((wd, vd))
    return out


def inertia_arrays(robot, q_lo, q_hi, values, algebra):
    """``regressor_bounds.inertia_enclosure`` before the armature and the symmetric
    intersection, as array code over the boxes in the arithmetic ``algebra``
    (``regressor_bounds._Ball`` or :class:`Box`): the oracle of the compiled ball kernel
    (``ball_kernels.inertia_kernel``), which performs the same operations box by box."""
    n = robot.n
    chain = rb._Chain(robot, q_lo, q_hi, algebra)
    A, B = chain.A, chain.B
    links = inertial_forward(chain)
    lo, hi = np.zeros((B, n, n)), np.zeros((B, n, n))
    f = m = None
    for k in range(n - 1, -1, -1):
        wd, vd = links[k]
        p = values[k]
        inertia = rb._inertia_tensors(values[k:k + 1])[0]
        mc = A.point(p[6:9])
        fk = A.add(A.scale(vd, p[9]), A.cross(wd, mc))
        mk = A.add(A.matvec(inertia, wd), A.cross(mc, vd))
        f, m = (fk, mk) if f is None else (A.add(fk, f), A.add(mk, m))
        zl, zh = A.z(f if chain.pris[k] else m)
        lo[:, k], hi[:, k] = zl, zh
        if k:
            f = chain.rot(k, f)
            m = A.add(chain.rot(k, m), A.cross(chain.p(k), f))
    return lo, hi


def column_groups(robot, q_lo, q_hi, columns, gravity=None):
    """``regressor_bounds._column_groups`` in interval boxes: per link k and joint i <= k,
    (the positions of the link's columns, i, (lo, hi) of shape (B, C, g))."""
    return rb._column_groups(robot, q_lo, q_hi, columns, gravity, Box)


def inertia_box(robot, q_lo, q_hi, values, armature=None):
    """Enclosures (lo, hi) (B, n, n) of D(q) over boxes in interval boxes: the array
    recursion, then the armature on the diagonal (rounded outward) and D_ij and D_ji
    intersected, as ``inertia_enclosure`` finishes its ball kernel's."""
    lo, hi = inertia_arrays(robot, np.asarray(q_lo, float), np.asarray(q_hi, float),
                            np.asarray(values, float), Box)
    arm = np.asarray(robot.armature if armature is None else armature, float)
    idx = np.arange(robot.n)
    lo[:, idx, idx] = np.nextafter(lo[:, idx, idx] + arm, -np.inf)
    hi[:, idx, idx] = np.nextafter(hi[:, idx, idx] + arm, np.inf)
    return np.maximum(lo, np.swapaxes(lo, 1, 2)), np.minimum(hi, np.swapaxes(hi, 1, 2))

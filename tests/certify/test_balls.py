"""Ball arithmetic: every operation encloses the exact values at points of its operands."""
import numpy as np

from gd_analyze.certify import balls


def _ball(rng, count):
    return rng.normal(size=(count, 3)), rng.uniform(0, 0.5, count)


def _inside(rng, ball):
    c, r = ball
    e = rng.normal(size=c.shape)
    e *= (r * rng.uniform(0, 1, r.shape) / np.linalg.norm(e, axis=1))[:, None]
    return c + e


def _contains(ball, x):
    return np.all(np.linalg.norm(x - ball[0], axis=-1) <= ball[1] + 1e-12)


def test_operations_enclose_point_values():
    rng = np.random.default_rng(0)
    a, b = _ball(rng, 300), _ball(rng, 300)
    M = rng.normal(size=(3, 3))
    for _ in range(30):
        x, y = _inside(rng, a), _inside(rng, b)
        assert _contains(balls.add(a, b), x + y)
        assert _contains(balls.cross(a, b), np.cross(x, y))
        assert _contains(balls.matvec(M, a), x @ M.T)
        assert _contains(balls.scale(a, -2.5), -2.5 * x)


def test_rotation_by_an_uncertain_angle_encloses_the_arc():
    rng = np.random.default_rng(1)
    a = _ball(rng, 300)
    mid = rng.uniform(-4, 4, 300)
    half = rng.uniform(0, 3.5, 300)
    for transpose in (False, True):
        out = balls.rot_z(a, mid, half, transpose)
        for _ in range(30):
            x = _inside(rng, a)
            th = mid + half * rng.uniform(-1, 1, 300)
            th = -th if transpose else th
            c, s = np.cos(th), np.sin(th)
            y = np.stack([c * x[:, 0] - s * x[:, 1], s * x[:, 0] + c * x[:, 1], x[:, 2]], -1)
            assert _contains(out, y)
    lo, hi = balls.z_interval(out)
    assert np.all(lo <= hi)

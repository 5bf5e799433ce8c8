"""The analytic references of the NN4DEM single-particle scenes (examples/free-fall, sliding)."""
import math


def apexes(heights, floor=0.01):
    """Local maxima of a height series above floor: the apex after each bounce."""
    return [heights[k] for k in range(1, len(heights) - 1)
            if heights[k] >= heights[k - 1] and heights[k] > heights[k + 1] and heights[k] > floor]


def bounce_apexes(drop, k, eta, m, count):
    """Apex heights of a sphere dropped from drop onto an infinitely heavy partner: linear spring k,
    absolute damping eta: each bounce keeps e^2 of the height, e = exp(-pi z / sqrt(1 - z^2)),
    z = eta / (2 sqrt(k m))."""
    z = eta / (2.0 * math.sqrt(k * m))
    e = math.exp(-math.pi * z / math.sqrt(1.0 - z * z))
    return [drop * e ** (2 * n) for n in range(1, count + 1)]


def slide_on_sphere(v0, mu, g, rc, dt=1e-6):
    """Distance along x a non-rotating sphere slides before it stops, starting at the top of a
    sphere of radius rc (centre distance) at speed v0 with Coulomb friction mu."""
    th, w = 0.0, v0 / rc
    while w > 0:
        normal = g * math.cos(th) - rc * w * w
        w += (g * math.sin(th) - mu * normal) / rc * dt
        th += w * dt
    return rc * math.sin(th)

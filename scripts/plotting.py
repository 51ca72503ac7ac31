"""Small 2D helpers shared by the render_*.py scripts (standard library only)."""
import math


def principal_frame(points):
    """A function mapping (x, y) into a frame centred on the points' centroid with their
    principal (longest) direction along x."""
    cx = sum(p[0] for p in points) / len(points)
    cy = sum(p[1] for p in points) / len(points)
    sxx = sum((p[0] - cx) ** 2 for p in points)
    syy = sum((p[1] - cy) ** 2 for p in points)
    sxy = sum((p[0] - cx) * (p[1] - cy) for p in points)
    t = -0.5 * math.atan2(2 * sxy, sxx - syy)
    c, s = math.cos(t), math.sin(t)

    def transform(p):
        return ((p[0] - cx) * c - (p[1] - cy) * s, (p[0] - cx) * s + (p[1] - cy) * c)
    return transform

"""Small helpers shared by the render_*.py scripts (standard library only): a principal frame
and a stacked layout for flat parts, and an orthographic view with Lambert shading for meshes."""
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


def stacked_svg(rows, width, widest, label_x):
    """SVG text of flat shapes stacked top to bottom at one scale, each labelled on the left.
    rows: (label, (x0, x1, y0, y1), draw) with the shape's bounding box and draw(P) returning
    its SVG elements, P mapping shape coordinates (y up) to pixels. A shape `widest` wide fills
    the width less 80 px; labels start at x = label_x px."""
    scale = (width - 80) / widest
    y = 20.0
    out = []
    for label, (x0, x1, y0, y1), draw in rows:
        def P(q, y=y, x0=x0, y1=y1):
            return 60 + scale * (q[0] - x0), y + scale * (y1 - q[1])
        out += draw(P)
        out.append(f'<text x="{label_x}" y="{y + scale * (y1 - y0) / 2 + 5:.1f}" '
                   f'font-family="sans-serif" font-size="14">{label}</text>')
        y += scale * (y1 - y0) + 16
    h = int(y + 10)
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{h}" '
           f'viewBox="0 0 {width} {h}"><rect width="100%" height="100%" fill="white"/>']
    return "\n".join(svg + out + ["</svg>"])


class View:
    """Orthographic view of 3D points: the model's `up` axis (x, y or z) vertical, turned by
    `azimuth` and tilted by `elevation` degrees, fitted to `width` pixels. Screen x is right, z up,
    y depth (larger = farther). `fit` lists the point indices to frame (default: all)."""

    LIGHT = (-0.5, -0.6, 0.6)

    def __init__(self, verts, up, azimuth, elevation, width, fit=None):
        order = {0: (1, 2, 0), 1: (2, 0, 1), 2: (0, 1, 2)}["xyz".index(up)]  # up axis -> z
        az, el = math.radians(azimuth), math.radians(elevation)
        self.pts = [self._turn(tuple(v[i] for i in order), az, el) for v in verts]
        used = range(len(self.pts)) if fit is None else fit
        xs = [self.pts[i][0] for i in used]
        zs = [self.pts[i][2] for i in used]
        span = max(max(xs) - min(xs), max(zs) - min(zs))
        self.width = width
        self.scale = 0.9 * width / span
        self.height = int(width * (max(zs) - min(zs)) / span) + int(0.1 * width)
        self.cx, self.cz = (max(xs) + min(xs)) / 2, (max(zs) + min(zs)) / 2
        ln = math.sqrt(sum(c * c for c in self.LIGHT))
        self.light = tuple(c / ln for c in self.LIGHT)

    @staticmethod
    def _turn(p, az, el):
        x, y, z = p
        ca, sa = math.cos(az), math.sin(az)
        x, y = ca * x - sa * y, sa * x + ca * y          # about the vertical axis
        ce, se = math.cos(el), math.sin(el)
        y, z = ce * y - se * z, se * y + ce * z          # tilt towards the viewer
        return x, y, z

    def screen(self, i):
        """Pixel position of point i."""
        p = self.pts[i]
        return (self.width / 2 + self.scale * (p[0] - self.cx),
                self.height / 2 - self.scale * (p[2] - self.cz))

    def face(self, quad):
        """(depth, lambert) of a quad facing the viewer, None if it faces away."""
        p = [self.pts[i] for i in quad]
        u = [p[2][k] - p[0][k] for k in range(3)]
        v = [p[3][k] - p[1][k] for k in range(3)]
        n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        nn = math.sqrt(sum(c * c for c in n)) or 1.0
        n = tuple(c / nn for c in n)
        if n[1] > 0:      # facing away from the viewer (viewer looks along +y)
            return None
        depth = sum(c[1] for c in p) / len(p)
        return depth, max(0.0, sum(n[k] * self.light[k] for k in range(3)))

    def svg_header(self):
        return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{self.width}" '
                f'height="{self.height}" viewBox="0 0 {self.width} {self.height}">'
                f'<rect width="100%" height="100%" fill="white"/>')

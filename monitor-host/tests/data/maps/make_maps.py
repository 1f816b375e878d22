#!/usr/bin/env python3
"""Writes the hand-made OpenDRIVE maps of the map tests (run from this folder; the outputs are
committed). Each map exercises what CARLA's towns do not: spirals, poly3, paramPoly3 with both
pRange, laneOffset, varying widths, elevation, a junction, an overpass, and broken files."""
import math

HEADER = '<?xml version="1.0" encoding="UTF-8"?>\n<OpenDRIVE>\n  <header revMajor="1" revMinor="4" name="{name}" version="1" vendor="sds-monitor tests"/>\n'


def cubic(tag, start_attr, start, a, b=0.0, c=0.0, d=0.0):
    return f'<{tag} {start_attr}="{start!r}" a="{a!r}" b="{b!r}" c="{c!r}" d="{d!r}"/>'


def lane(lid, typ="driving", widths=((0.0, 3.5),), pred=None, succ=None, border=False):
    link = ""
    if pred is not None or succ is not None:
        link = "<link>" + (f'<predecessor id="{pred}"/>' if pred is not None else "") + (f'<successor id="{succ}"/>' if succ is not None else "") + "</link>"
    tag = "border" if border else "width"
    ws = "".join(cubic(tag, "sOffset", *w) for w in widths)
    return f'        <lane id="{lid}" type="{typ}" level="false">{link}{ws}</lane>\n'


def section(s, left=(), right=()):
    out = f'      <laneSection s="{s!r}">\n'
    if left:
        out += "       <left>\n" + "".join(left) + "       </left>\n"
    out += '       <center><lane id="0" type="none" level="false"/></center>\n'
    if right:
        out += "       <right>\n" + "".join(right) + "       </right>\n"
    return out + "      </laneSection>\n"


def road(rid, length, geoms, sections, junction=-1, pred=None, succ=None, elevation=(), offsets=()):
    link = ""
    if pred or succ:
        link = "    <link>" + (pred or "") + (succ or "") + "</link>\n"
    g = "".join(
        f'      <geometry s="{s!r}" x="{x!r}" y="{y!r}" hdg="{h!r}" length="{l!r}">{shape}</geometry>\n'
        for (s, x, y, h, l, shape) in geoms
    )
    el = "".join("      " + cubic("elevation", "s", *e) + "\n" for e in elevation)
    off = "".join("      " + cubic("laneOffset", "s", *o) + "\n" for o in offsets)
    return (
        f'  <road name="Road {rid}" length="{length!r}" id="{rid}" junction="{junction}">\n{link}'
        f"    <planView>\n{g}    </planView>\n    <elevationProfile>\n{el}    </elevationProfile>\n"
        f"    <lanes>\n{off}{''.join(sections)}    </lanes>\n  </road>\n"
    )


def link(kind, etype, eid, contact=None):
    c = f' contactPoint="{contact}"' if contact else ""
    return f'<{kind} elementType="{etype}" elementId="{eid}"{c}/>'


def two_way(length, w=3.5):
    return [section(0.0, left=[lane(1, widths=((0.0, w),))], right=[lane(-1, widths=((0.0, w),))])]


def write(name, body):
    with open(name + ".xodr", "w") as f:
        f.write(HEADER.format(name=name) + body + "</OpenDRIVE>\n")


def gl_arc(speed, a, b, n=2000):
    """Arc length by composite Simpson (an integration independent of the library's)."""
    h = (b - a) / n
    s = speed(a) + speed(b)
    for i in range(1, n):
        s += (4 if i % 2 else 2) * speed(a + i * h)
    return s * h / 3


# Spiral: clothoid from curvature 0 to 0.04 over 50 m, then back to 0 over 50 m (the second
# starts where the first ends: position by the Fresnel series).
def clothoid_end(L, k1):
    a = k1 / (2 * L)  # heading = a u^2
    x = sum((-1) ** n * a ** (2 * n) * L ** (4 * n + 1) / (math.factorial(2 * n) * (4 * n + 1)) for n in range(20))
    y = sum((-1) ** n * a ** (2 * n + 1) * L ** (4 * n + 3) / (math.factorial(2 * n + 1) * (4 * n + 3)) for n in range(20))
    return x, y, a * L * L


x1, y1, h1 = clothoid_end(50.0, 0.04)
write(
    "spiral",
    road(
        1,
        100.0,
        [
            (0.0, 0.0, 0.0, 0.0, 50.0, '<spiral curvStart="0.0" curvEnd="0.04"/>'),
            (50.0, x1, y1, h1, 50.0, '<spiral curvStart="0.04" curvEnd="0.0"/>'),
        ],
        [section(0.0, left=[lane(1)], right=[lane(-1), lane(-2, widths=((0.0, 3.0),))])],
    ),
)

# poly3: v = 0.5 + 0.01 u^2 - 0.0001 u^3 for u in [0, 40], with elevation.
pc = (0.5, 0.0, 0.01, -0.0001)
poly_len = gl_arc(lambda u: math.hypot(1.0, 2 * pc[2] * u + 3 * pc[3] * u * u), 0.0, 40.0)
write(
    "poly3",
    road(
        1,
        poly_len,
        [(0.0, 10.0, 5.0, 0.3, poly_len, f'<poly3 a="{pc[0]!r}" b="{pc[1]!r}" c="{pc[2]!r}" d="{pc[3]!r}"/>')],
        two_way(poly_len),
        elevation=[(0.0, 1.0, 0.05, 0.001, -0.00001)],
    ),
)

# paramPoly3, both pRange: road 1 over p in [0, 30] (arcLength: p runs to `length` = 30, and bU is
# chosen so that the curve is 30 m long too), road 2 over [0, 1] (normalized).
v1 = (0.0, 0.0, 0.02, -0.0003)


def len_u1(bu):
    u = (0.0, bu, -0.004, 0.0)
    return gl_arc(lambda p: math.hypot(u[1] + 2 * u[2] * p + 3 * u[3] * p * p, v1[1] + 2 * v1[2] * p + 3 * v1[3] * p * p), 0.0, 30.0)


lo, hi = 0.5, 1.5
for _ in range(100):
    mid = 0.5 * (lo + hi)
    lo, hi = (mid, hi) if len_u1(mid) < 30.0 else (lo, mid)
u1 = (0.0, 0.5 * (lo + hi), -0.004, 0.0)
len1 = 30.0
u2 = (0.0, 35.0, -6.0, 1.0)
v2 = (0.0, 2.0, 9.0, -4.0)
len2 = gl_arc(lambda p: math.hypot(u2[1] + 2 * u2[2] * p + 3 * u2[3] * p * p, v2[1] + 2 * v2[2] * p + 3 * v2[3] * p * p), 0.0, 1.0)


def pp3(u, v, rng):
    return f'<paramPoly3 aU="{u[0]!r}" bU="{u[1]!r}" cU="{u[2]!r}" dU="{u[3]!r}" aV="{v[0]!r}" bV="{v[1]!r}" cV="{v[2]!r}" dV="{v[3]!r}" pRange="{rng}"/>'


write(
    "parampoly3",
    road(1, len1, [(0.0, 0.0, 0.0, 0.1, len1, pp3(u1, v1, "arcLength"))], two_way(len1))
    + road(2, len2, [(0.0, 0.0, 100.0, -0.2, len2, pp3(u2, v2, "normalized"))], two_way(len2)),
)

# laneOffset and varying widths on a straight road along x, two lane sections.
write(
    "lane_offset",
    road(
        1,
        80.0,
        [(0.0, 0.0, 0.0, 0.0, 80.0, "<line/>")],
        [
            section(
                0.0,
                left=[lane(1, widths=((0.0, 3.0, 0.01),), succ=1)],
                right=[
                    lane(-1, widths=((0.0, 3.0, 0.0, 0.001, -0.00001), (30.0, 3.6)), succ=-1),
                    lane(-2, "shoulder", widths=((0.0, 1.0),)),
                ],
            ),
            section(
                40.0,
                left=[lane(1, widths=((0.0, 3.4),), pred=1)],
                right=[lane(-1, widths=((0.0, 3.6, -0.01),), pred=-1), lane(-2, widths=((0.0, 0.0, 0.1),))],
            ),
        ],
        offsets=[(0.0, 0.5, 0.02, -0.001, 0.00001), (40.0, -0.3)],
    ),
)

# A junction: road 1 (west, eastbound lane -1) into junction 100: straight (road 10 -> road 2),
# right turn (road 11, radius 10 -> road 3, south) and left turn (road 12 -> road 4, north).
R = 10.0
w_turn = math.pi / 2 * R
write(
    "junction",
    road(1, 50.0, [(0.0, -50.0, 0.0, 0.0, 50.0, "<line/>")], two_way(50.0), succ=link("successor", "junction", 100))
    + road(2, 50.0, [(0.0, 20.0, 0.0, 0.0, 50.0, "<line/>")], two_way(50.0), pred=link("predecessor", "junction", 100))
    + road(3, 50.0, [(0.0, R, -R, -math.pi / 2, 50.0, "<line/>")], two_way(50.0), pred=link("predecessor", "junction", 100))
    + road(4, 50.0, [(0.0, R, R, math.pi / 2, 50.0, "<line/>")], two_way(50.0), pred=link("predecessor", "junction", 100))
    + road(10, 20.0, [(0.0, 0.0, 0.0, 0.0, 20.0, "<line/>")], [section(0.0, right=[lane(-1, pred=-1, succ=-1)])], junction=100,
           pred=link("predecessor", "road", 1, "end"), succ=link("successor", "road", 2, "start"))
    + road(11, w_turn, [(0.0, 0.0, 0.0, 0.0, w_turn, f'<arc curvature="{-1 / R!r}"/>')], [section(0.0, right=[lane(-1, pred=-1, succ=-1)])], junction=100,
           pred=link("predecessor", "road", 1, "end"), succ=link("successor", "road", 3, "start"))
    + road(12, w_turn, [(0.0, 0.0, 0.0, 0.0, w_turn, f'<arc curvature="{1 / R!r}"/>')], [section(0.0, right=[lane(-1, pred=-1, succ=-1)])], junction=100,
           pred=link("predecessor", "road", 1, "end"), succ=link("successor", "road", 4, "start"))
    + '  <junction id="100" name="junction">\n'
    + "".join(
        f'    <connection id="{i}" incomingRoad="1" connectingRoad="{c}" contactPoint="start"><laneLink from="-1" to="-1"/></connection>\n'
        for i, c in enumerate((10, 11, 12))
    )
    + "  </junction>\n",
)

# An overpass: road 1 along x at height 0, road 2 along y at height 8 crossing above it.
write(
    "overpass",
    road(1, 100.0, [(0.0, -50.0, 0.0, 0.0, 100.0, "<line/>")], two_way(100.0))
    + road(2, 100.0, [(0.0, 0.0, -50.0, math.pi / 2, 100.0, "<line/>")], two_way(100.0), elevation=[(0.0, 8.0)]),
)

# Broken maps.
ok_road = road(1, 50.0, [(0.0, 0.0, 0.0, 0.0, 50.0, "<line/>")], two_way(50.0))
text = HEADER.format(name="broken_truncated") + ok_road + "</OpenDRIVE>\n"
with open("broken_truncated.xodr", "w") as f:
    f.write(text[: len(text) * 2 // 3])
write("broken_negative_length", ok_road + road(7, 50.0, [(0.0, 0.0, 10.0, 0.0, 20.0, "<line/>"), (20.0, 20.0, 10.0, 0.0, -30.0, "<line/>")], two_way(50.0)))
write("broken_plan_gap", road(8, 50.0, [(0.0, 0.0, 0.0, 0.0, 20.0, "<line/>"), (30.0, 30.0, 0.0, 0.0, 20.0, "<line/>")], two_way(50.0)))
write("broken_road_length", road(9, 100000.0, [(0.0, 0.0, 0.0, 0.0, 50.0, "<spiral curvStart=\"0.0\" curvEnd=\"0.04\"/>")], two_way(100000.0)))
write("broken_border", road(5, 50.0, [(0.0, 0.0, 0.0, 0.0, 50.0, "<line/>")], [section(0.0, right=[lane(-1), lane(-2, border=True)])]))
write("broken_missing_road", road(3, 50.0, [(0.0, 0.0, 0.0, 0.0, 50.0, "<line/>")], two_way(50.0), succ=link("successor", "road", 42, "start")))

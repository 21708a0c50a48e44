#!/usr/bin/env python3
"""Writes garments/skirt.obj: a flared skirt for urdf/mannequin.urdf, a quad mesh in the world
frame of the demo (pelvis frame at z = 0.96 m). The waistband ring (the first `AROUND` vertices)
is an ellipse 1 cm clear of the torso box at z = 1.08 m; the hem ring, 0.46 m lower, flares
front to back (semi-axes 0.30 x 0.17 m): the hanging arms leave only 2 cm between torso and
forearm, so the skirt widens sideways just enough to pass the thighs inside the hands. Quads run
counter-clockwise seen from outside, so their normals point out.
Usage: scripts/make_skirt.py [out.obj]"""
import math
import sys

AROUND, DOWN = 24, 8
WAIST_Z, HEM_Z = 1.08, 0.62
WAIST = (0.12, 0.155)  # semi-axes along x and y [m]
HEM = (0.30, 0.17)


def main(path):
    lines = ['# Flared skirt for urdf/mannequin.urdf, made by scripts/make_skirt.py',
             '# %d x %d quads; vertices 0..%d are the waistband (attach them to frame pelvis)'
             % (AROUND, DOWN, AROUND - 1)]
    for j in range(DOWN + 1):
        s = j / DOWN
        z = WAIST_Z + s * (HEM_Z - WAIST_Z)
        ax = WAIST[0] + s * (HEM[0] - WAIST[0])
        ay = WAIST[1] + s * (HEM[1] - WAIST[1])
        for i in range(AROUND):
            a = 2.0 * math.pi * i / AROUND
            lines.append('v %.6f %.6f %.6f' % (ax * math.cos(a), ay * math.sin(a), z))
    for j in range(DOWN):
        for i in range(AROUND):
            a, b = j * AROUND + i, j * AROUND + (i + 1) % AROUND
            c, d = b + AROUND, a + AROUND
            # Going round counter-clockwise (seen from above) and down: a, d, c, b faces outward.
            lines.append('f %d %d %d %d' % (a + 1, d + 1, c + 1, b + 1))
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')


if __name__ == '__main__':
    main(sys.argv[1] if len(sys.argv) > 1 else 'garments/skirt.obj')

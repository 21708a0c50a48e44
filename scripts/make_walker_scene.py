#!/usr/bin/env python3
"""Writes scenes/simulate_walker.yaml: the walker of bench/curtain_benchmark.cpp (issue 11's
row) for `simulate`. A 0.6 x 0.6 m cotton garment of 45 x 45 quads hangs from its pinned top
row at hip height, 1 cm in front of two leg capsules (R 7 cm, 0.85 m from hip to foot) that
swing +-0.4 rad about the hip axis out of phase, one stride per second. simulate's colliders
move by keyframes (linear in position, spherical in rotation): one every 1/48 s.
Usage: scripts/make_walker_scene.py [out.yaml] [seconds]"""
import math
import sys

HIP_Z, LEG, RADIUS, HIP_X = 0.9, 0.85, 0.07, 0.1
AMPLITUDE, OMEGA = 0.4, 2.0 * math.pi  # [rad], [rad/s]
RATE = 48  # keyframes per second


def leg(side, seconds):
    lines = ['  - name: %s_leg' % ('left' if side < 0 else 'right'),
             '    capsule: {radius: %.2f, length: %.2f}' % (RADIUS, LEG),
             '    friction: 0.3',
             '    motion:',
             '      keyframes:']
    for k in range(int(round(seconds * RATE)) + 1):
        t = k / RATE
        theta = side * AMPLITUDE * math.sin(OMEGA * t)  # forward, towards -y
        # The capsule's axis (local z) along the leg: turned about x by -theta; its centre
        # halfway down the leg.
        y = -0.5 * LEG * math.sin(theta)
        z = HIP_Z - 0.5 * LEG * math.cos(theta)
        lines.append('        - {time: %.6f, position: [%.2f, %.6f, %.6f], rotation: [%.6f, 0, 0]}'
                     % (t, side * HIP_X, y, z, -theta))
    return lines


def main(path, seconds):
    lines = ['# simulate: the walker of bench/curtain_benchmark.cpp (issue 11\'s row), written by',
             '# scripts/make_walker_scene.py: a 0.6 x 0.6 m cotton garment of 45 x 45 quads hangs',
             '# from its pinned top row at hip height, 1 cm in front of two leg capsules that swing',
             '# +-0.4 rad about the hip axis out of phase, one stride per second (keyframes every',
             '# 1/48 s); frames of 1/24 s on the Lagrangian implicit step.',
             'name: walker',
             'duration: %g' % seconds,
             'frame_rate: 24',
             'world: {integration: lagrangian_implicit, max_time_step: 0.0166667}',
             'bodies:',
             '  - name: garment',
             '    rectangle: {size: [0.6, 0.6], cells: [45, 45]}',
             '    position: [0, %.2f, %.2f]' % (-RADIUS - 0.01, HIP_Z - 0.3),
             '    rotation: [1.5707963, 0, 0]',
             '    material: cotton_eischen',
             '    pins: {plane: {axis: z, value: %.2f, tolerance: 1.0e-4}}' % HIP_Z,
             'colliders:']
    for side in (-1.0, 1.0):
        lines += leg(side, seconds)
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')


if __name__ == '__main__':
    main(sys.argv[1] if len(sys.argv) > 1 else 'scenes/simulate_walker.yaml',
         float(sys.argv[2]) if len(sys.argv) > 2 else 1.0)

#!/usr/bin/env python3
"""Writes the example trajectories of the book's Trajectories section (no dependencies):
`trajectory/ground_truth.tum`, a winding, climbing 30 s path at 10 Hz as a sensor sequence's
ground truth, and `trajectory/estimate.tum`, an odometry run along it that turns 0.02 degrees
a pose too much and runs 1 % long, stamped 3 ms late. Run from examples/scoring/."""
import math


def pose(s):
    x = 1.5 * s + 4.0 * math.sin(0.1 * s)
    y = 3.0 * math.sin(0.15 * s) + 0.3 * s
    z = 0.05 * s
    return x, y, z, 0.2 * s


def main():
    n = 300
    truth = [pose(k * 0.1) for k in range(n)]
    with open("trajectory/ground_truth.tum", "w") as f:
        f.write("# t x y z qx qy qz qw\n")
        for k, (x, y, z, a) in enumerate(truth):
            f.write(f"{k * 0.1:.3f} {x:.6f} {y:.6f} {z:.6f} 0 0 {math.sin(a / 2):.9f} {math.cos(a / 2):.9f}\n")
    drift = math.radians(0.02)
    px, py, pz = truth[0][:3]
    with open("trajectory/estimate.tum", "w") as f:
        f.write("# t x y z qx qy qz qw\n")
        for k in range(n):
            a = truth[k][3] + k * drift
            f.write(f"{k * 0.1 + 0.003:.3f} {px:.6f} {py:.6f} {pz:.6f} 0 0 {math.sin(a / 2):.9f} {math.cos(a / 2):.9f}\n")
            if k + 1 < n:
                # The true step, turned by the drift so far and 1 % long.
                dx, dy = truth[k + 1][0] - truth[k][0], truth[k + 1][1] - truth[k][1]
                c, s = math.cos(k * drift), math.sin(k * drift)
                px += 1.01 * (c * dx - s * dy)
                py += 1.01 * (s * dx + c * dy)
                pz += 1.01 * (truth[k + 1][2] - truth[k][2])


if __name__ == "__main__":
    main()

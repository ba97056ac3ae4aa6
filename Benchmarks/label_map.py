"""The label map the label benchmarks share: 100 labels, each a 13-voxel box
with a ball of radius 6 cut out at one of its edges, at random places in an N^3 int16 volume (seed 1;
later labels overwrite earlier ones where they overlap)."""
import numpy as np


def hundred_label_map(n):
    rng = np.random.default_rng(1)
    data = np.zeros((n, n, n), np.int16)
    g = np.arange(-8, 9)
    zz, yy, xx = np.meshgrid(g, g, g, indexing="ij")
    shape = (np.abs(xx) <= 6) & (np.abs(yy) <= 6) & (np.abs(zz) <= 6) & ((xx - 6) ** 2 + (yy - 6) ** 2 + zz ** 2 > 36)
    for label in range(1, 101):
        c = rng.integers(10, n - 10, 3)
        block = data[c[0] - 8:c[0] + 9, c[1] - 8:c[1] + 9, c[2] - 8:c[2] + 9]
        block[shape] = label
    return data

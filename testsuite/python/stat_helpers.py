"""Statistics shared by the thermostat tests (test_langevin, test_brownian)."""
import numpy as np


def block_mean_err(x, n_blocks):
    """Mean and error of the mean of per-particle values x[..., n_particles],
    from n_blocks independent blocks of particles."""
    blocks = np.array_split(np.arange(x.shape[-1]), n_blocks)
    b = np.array([x[..., i].mean(axis=-1) for i in blocks])
    return b.mean(axis=0), b.std(axis=0, ddof=1) / np.sqrt(n_blocks)

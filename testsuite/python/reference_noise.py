"""An independent Python implementation of the engine's counter-based noise
(src/utils/include/utils/noise.hpp), for tests that check forces to the last
bit: Philox4x64-10 written from the round function of Salmon et al. (SC11)."""
import numpy as np

MASK = (1 << 64) - 1
M0, M1 = 0xD2E7470EE14C6C93, 0xCA5A826395121157
W0, W1 = 0x9E3779B97F4A7C15, 0xBB67AE8584CAA73B
KEY1 = 0x6d61726231  # the second key word ("marb1")
SALT_DPD = 1           # RNGSalt::dpd
SALT_WALL = 3          # RNGSalt::tunable_slip_wall


def philox4x64(ctr, key):
    """Philox4x64-10 of a 4-word counter and a 2-word key."""
    c = list(ctr)
    k0, k1 = key
    for rnd in range(10):
        if rnd:
            k0, k1 = (k0 + W0) & MASK, (k1 + W1) & MASK
        p0, p1 = M0 * c[0], M1 * c[2]
        c = [(p1 >> 64) ^ c[1] ^ k0, p1 & MASK, (p0 >> 64) ^ c[3] ^ k1, p0 & MASK]
    return c


def uniform3(seed, salt, counter, id_a, id_b):
    """Three numbers in (-1/2, 1/2] as the engine draws them for (counter, id_a, id_b, salt)."""
    r = philox4x64([counter, int(id_a), int(id_b), salt], [seed, KEY1])
    return np.array([((x >> 11) + 1.0) * 2.0**-53 - 0.5 for x in r[:3]])

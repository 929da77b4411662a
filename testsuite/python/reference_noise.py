"""An independent Python implementation of the engine's counter-based noise,
for tests that check forces to the last bit, written from the round function
of Salmon et al. (SC11): Philox4x64-10 (src/utils/include/utils/noise.hpp:
walls, Langevin, SRD, ...) and Philox4x32-10 of the pair noise of the
dissipative pair kernels (src/utils/include/utils/philox4x32.hpp:
pair_uniform3 / pair_noise)."""
import numpy as np

MASK = (1 << 64) - 1
M0, M1 = 0xD2E7470EE14C6C93, 0xCA5A826395121157
W0, W1 = 0x9E3779B97F4A7C15, 0xBB67AE8584CAA73B
KEY1 = 0x6d61726231  # the second key word ("marb1")
SALT_DPD = 1           # RNGSalt::dpd
SALT_WALL = 3          # RNGSalt::tunable_slip_wall


def _philox4(ctr, key, bits, m0, m1, w0, w1):
    """Philox4xW-10 (Salmon et al. 2011) with W = @p bits-bit words."""
    mask = (1 << bits) - 1
    c = list(ctr)
    k0, k1 = key
    for rnd in range(10):
        if rnd:
            k0, k1 = (k0 + w0) & mask, (k1 + w1) & mask
        p0, p1 = m0 * c[0], m1 * c[2]
        c = [(p1 >> bits) ^ c[1] ^ k0, p1 & mask, (p0 >> bits) ^ c[3] ^ k1, p0 & mask]
    return c


def philox4x64(ctr, key):
    """Philox4x64-10 of a 4-word counter and a 2-word key."""
    return _philox4(ctr, key, 64, M0, M1, W0, W1)


def uniform3(seed, salt, counter, id_a, id_b):
    """Three numbers in (-1/2, 1/2] as the engine draws them for (counter, id_a, id_b, salt)."""
    r = philox4x64([counter, int(id_a), int(id_b), salt], [seed, KEY1])
    return np.array([((x >> 11) + 1.0) * 2.0**-53 - 0.5 for x in r[:3]])


# --------------------------------------------------------------------------
# The pair noise of the dissipative pair kernels (DPD, lubrication):
# Philox4x32-10 (src/utils/include/utils/philox4x32.hpp).
# --------------------------------------------------------------------------
MASK32 = (1 << 32) - 1
M0_32, M1_32 = 0xD2511F53, 0xCD9E8D57
W0_32, W1_32 = 0x9E3779B9, 0xBB67AE85


def philox4x32(ctr, key):
    """Philox4x32-10 of a 4-word counter and a 2-word key (32-bit words)."""
    return _philox4(ctr, key, 32, M0_32, M1_32, W0_32, W1_32)


def pair_uniform3(seed, salt, counter, id_lo, id_hi):
    """The three uniforms in (-1/2, 1/2) of the unordered pair (id_lo < id_hi),
    unsigned: counter words (id_lo, id_hi, step low, step high + salt 2^24), key = seed."""
    ctr = [int(id_lo), int(id_hi), counter & MASK32, ((counter >> 32) + (salt << 24)) & MASK32]
    r = philox4x32(ctr, [seed & MASK32, (seed >> 32) & MASK32])
    return np.array([(x + 0.5) * 2.0**-32 - 0.5 for x in r[:3]])


def pair_noise(seed, salt, counter, id_i, id_j):
    """pair_uniform3 of the pair signed by id order (+ if id_i < id_j): F_j = -F_i."""
    if id_i < id_j:
        return pair_uniform3(seed, salt, counter, id_i, id_j)
    return -pair_uniform3(seed, salt, counter, id_j, id_i)

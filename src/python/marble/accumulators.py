"""Accumulators (espressomd-shaped), updated in C++ during ``integrator.run``
when added to ``system.auto_update_accumulators`` (doc/analysis.md):

- :class:`Correlator`: multiple-tau correlator (Ramirez, Sinha, Gubbins 2010),
- :class:`TimeSeries`: stores every sample,
- :class:`MeanVarianceCalculator`: running mean and variance,

and :func:`fft_correlate`, the exact all-origins correlation of a stored series.
"""
import numpy as np

from . import _marble
from .observables import Observable, _register_system

_OPERATIONS = ("scalar_product", "componentwise_product", "square_distance_componentwise")


def _check_kwargs(name, kwargs, allowed, required):
    unknown = set(kwargs) - set(allowed)
    if unknown:
        raise ValueError(f"unknown parameter(s) {sorted(unknown)} for {name} "
                         f"(allowed: {', '.join(allowed)})")
    for r in required:
        if kwargs.get(r) is None:
            raise ValueError(f"parameter '{r}' is required for {name}")


def _check_obs(name, obs):
    if not isinstance(obs, Observable):
        raise ValueError(f"parameter '{name}' must be a marble.observables observable, "
                         f"got {type(obs).__name__}")
    if obs._obs is None:
        raise ValueError(f"parameter '{name}': {type(obs).__name__} is evaluated in Python and "
                         f"cannot be sampled by the C++ accumulators; call calculate() in a "
                         f"Python loop around integrator.run")
    return obs


class _Accumulator:
    """Common part: the system the observable belongs to, delta_N, update()."""

    def _system(self):
        return self._obs_py._system

    @property
    def delta_N(self):
        """Sampling interval in integration steps."""
        return self._acc.delta_N

    def __reduce__(self):
        """Pickled with its constructor arguments and its full C++ state (the
        correlator's hierarchy and sums, the series, the running moments), so
        a restored accumulator continues exactly where this one stopped."""
        return (_restore_accumulator,
                (type(self), self._ctor_kwargs, self._time_step,
                 _marble.accumulator_get_state(self._acc)))

    def update(self):
        """Take one sample now (the integrator does this every delta_N steps
        once the accumulator is in ``system.auto_update_accumulators``)."""
        self._acc.update(self._system()._core)


class Correlator(_Accumulator):
    """Multiple-tau correlator C(tau) = < op(obs1(t0), obs2(t0 + tau)) > averaged over t0.

    Parameters
    ----------
    obs1 : observable; obs2 : observable, optional (default obs1, same size)
    tau_lin : even int >= 2 (default 16)
        Lags 0..tau_lin at full resolution; each further level doubles the lag
        spacing and adds lags (tau_lin/2, tau_lin] x 2^level.
    tau_max : float > 0
        Largest lag time to cover (the lags reach at least tau_max).
    delta_N : int >= 1 (default 1)
        Sampling interval in steps; sample spacing dt = delta_N * system.time_step.
    corr_operation : "scalar_product" (sum over all values, result (n_lags, 1)),
        "componentwise_product" or "square_distance_componentwise" (result
        (n_lags, \\*obs.shape())).
    compress1, compress2 : "discard1" (keep the newer of two values, default),
        "discard2" (keep the older) or "linear" (average).
    """

    _allowed = ("obs1", "obs2", "tau_lin", "tau_max", "delta_N", "corr_operation",
                "compress1", "compress2")

    def __init__(self, **kwargs):
        self._build(kwargs, None)

    def _build(self, kwargs, time_step):
        _check_kwargs("Correlator", kwargs, self._allowed, ("obs1", "tau_max", "corr_operation"))
        self._ctor_kwargs = dict(kwargs)
        self._obs_py = _check_obs("obs1", kwargs["obs1"])
        obs2 = kwargs.get("obs2")
        if obs2 is not None:
            _check_obs("obs2", obs2)
            if obs2._system is not self._obs_py._system:
                raise ValueError("parameters 'obs1' and 'obs2' belong to different systems")
        self._obs2_py = obs2
        op = kwargs["corr_operation"]
        if op not in _OPERATIONS:
            raise ValueError(f"parameter 'corr_operation' must be one of {', '.join(_OPERATIONS)}; "
                             f"got {op!r}")
        c1 = kwargs.get("compress1", "discard1")
        c2 = kwargs.get("compress2", c1)
        for name, c in (("compress1", c1), ("compress2", c2)):
            if not isinstance(c, str):
                raise ValueError(f"parameter '{name}' must be one of discard1, discard2, linear")
        self._params = dict(tau_lin=kwargs.get("tau_lin", 16), tau_max=kwargs["tau_max"],
                            delta_N=kwargs.get("delta_N", 1), corr_operation=op,
                            compress1=c1, compress2=c2)
        self._time_step = self._system().time_step if time_step is None else time_step
        self._acc = _marble.Correlator(
            self._obs_py._obs, None if obs2 is None else obs2._obs, self._params["tau_lin"],
            self._params["tau_max"], self._params["delta_N"], self._time_step, op, c1, c2)

    @property
    def obs1(self):
        """The first observable."""
        return self._obs_py

    @property
    def obs2(self):
        """The second observable (``obs1`` for an autocorrelation)."""
        return self._obs2_py if self._obs2_py is not None else self._obs_py

    @property
    def tau_lin(self):
        """Number of lags per level of the multiple-tau hierarchy."""
        return self._acc.tau_lin

    @property
    def tau_max(self):
        """Largest lag time to cover (the lags reach at least tau_max)."""
        return self._acc.tau_max

    @property
    def corr_operation(self):
        """The correlation operation (``scalar_product``, ``componentwise_product``, ``square_distance_componentwise``)."""
        return self._acc.corr_operation

    @property
    def hierarchy_depth(self):
        """Number of levels of the multiple-tau hierarchy."""
        return self._acc.hierarchy_depth

    @property
    def n_samples(self):
        """Samples taken so far."""
        return self._acc.n_samples

    def get_params(self):
        """The constructor parameters, as a dict."""
        return dict(self._params, obs1=self.obs1, obs2=self.obs2)

    def result(self):
        """Correlation for each lag, shape (n_lags, 1) for scalar_product, else
        (n_lags, \\*obs1.shape()). NaN for lags not reached yet."""
        return self._acc.result()

    def lag_times(self):
        """Lag times (n_lags,) = lag in samples * delta_N * time_step."""
        return self._acc.lag_times()

    def sample_sizes(self):
        """Number of pairs averaged per lag (n_lags,)."""
        return np.asarray(self._acc.sample_sizes(), dtype=np.int64)

    def finalize(self):
        """Stop accepting samples (ESPResSo compatibility). The compression is
        eager, so no data waits in the hierarchy: at most one unpaired value per
        level is dropped, and the results are final already."""
        self._acc.finalize()


class TimeSeries(_Accumulator):
    """Stores every sample of ``obs`` (every delta_N steps)."""

    _allowed = ("obs", "delta_N")

    def __init__(self, **kwargs):
        self._build(kwargs, None)

    def _build(self, kwargs, time_step):
        _check_kwargs("TimeSeries", kwargs, self._allowed, ("obs",))
        self._ctor_kwargs, self._time_step = dict(kwargs), time_step
        self._obs_py = _check_obs("obs", kwargs["obs"])
        self._acc = _marble.TimeSeries(self._obs_py._obs, kwargs.get("delta_N", 1))

    def time_series(self):
        """Samples, shape (n_samples, \\*obs.shape())."""
        return self._acc.time_series()

    def clear(self):
        """Drop every stored sample."""
        self._acc.clear()

    @property
    def n_samples(self):
        """Number of samples stored."""
        return self._acc.n_samples


class MeanVarianceCalculator(_Accumulator):
    """Running mean and sample variance (Welford) of ``obs``."""

    _allowed = ("obs", "delta_N")

    def __init__(self, **kwargs):
        self._build(kwargs, None)

    def _build(self, kwargs, time_step):
        _check_kwargs("MeanVarianceCalculator", kwargs, self._allowed, ("obs",))
        self._ctor_kwargs, self._time_step = dict(kwargs), time_step
        self._obs_py = _check_obs("obs", kwargs["obs"])
        self._acc = _marble.MeanVarianceCalculator(self._obs_py._obs, kwargs.get("delta_N", 1))

    def mean(self):
        """Running mean of the samples (shape of the observable)."""
        return self._acc.mean()

    def variance(self):
        """Sample variance (ddof = 1), NaN before 2 samples."""
        return self._acc.variance()

    def std_error(self):
        """sqrt(variance / n): the standard error of the mean for
        uncorrelated samples only (use marble.diffusion.blocking otherwise)."""
        return np.sqrt(self.variance() / self.n_samples)

    @property
    def n_samples(self):
        """Number of samples taken."""
        return self._acc.n_samples


class AutoUpdateAccumulators:
    """``system.auto_update_accumulators``: accumulators the integrator updates."""

    def __init__(self, system):
        self._system = system
        self._list = []
        _register_system(system)

    def add(self, accumulator):
        """Sample ``accumulator`` every ``accumulator.delta_N`` steps inside ``integrator.run``."""
        if not isinstance(accumulator, _Accumulator):
            raise ValueError("only marble.accumulators objects can be added, got "
                             f"{type(accumulator).__name__}")
        if accumulator._system() is not self._system:
            raise ValueError("the accumulator's observable belongs to another system")
        self._system._core.auto_update_add(accumulator._acc)
        self._list.append(accumulator)

    def _restore(self, accumulator):
        """Unpickling: re-register without the checks (same order as saved)."""
        self._system._core.auto_update_add(accumulator._acc)
        self._list.append(accumulator)

    def remove(self, accumulator):
        """Stop sampling ``accumulator``."""
        if accumulator not in self._list:
            raise ValueError("this accumulator is not in auto_update_accumulators")
        self._system._core.auto_update_remove(accumulator._acc)
        self._list.remove(accumulator)

    def clear(self):
        """Stop sampling every accumulator."""
        self._system._core.auto_update_clear()
        self._list.clear()

    def __len__(self):
        return len(self._list)

    def __iter__(self):
        return iter(list(self._list))

    def __contains__(self, item):
        return item in self._list

    def __getitem__(self, k):
        return self._list[k]


def _restore_accumulator(cls, kwargs, time_step, state):
    acc = cls.__new__(cls)
    acc._build(kwargs, time_step)
    _marble.accumulator_set_state(acc._acc, state)
    return acc


def have_fftw():
    """True if this build computes fft_correlate with FFTW."""
    return bool(_marble.have_fftw())


def _numpy_correlate(x, y, operation, max_lag):
    """Same as the C++ FFT path with numpy.fft (x, y: (T, n))."""
    T = x.shape[0]
    same = y is x
    N = 1 << int(np.ceil(np.log2(2 * T)))
    norm = (T - np.arange(max_lag + 1))[:, None]
    if operation == "square_distance_componentwise":
        shift = x.mean(axis=0)
        x = x - shift
        y = x if same else y - shift
    fx = np.fft.rfft(x, n=N, axis=0)
    fy = fx if same else np.fft.rfft(y, n=N, axis=0)
    cross = np.fft.irfft(np.conj(fx) * fy, n=N, axis=0)[:max_lag + 1]
    if operation == "scalar_product":
        return cross.sum(axis=1, keepdims=True) / norm
    if operation == "componentwise_product":
        return cross / norm
    k = np.arange(max_lag + 1)
    px = np.concatenate([np.zeros((1, x.shape[1])), np.cumsum(x * x, axis=0)])
    py = np.concatenate([np.zeros((1, y.shape[1])), np.cumsum(y * y, axis=0)])
    out = np.maximum((px[T - k] + (py[T] - py[k]) - 2.0 * cross) / norm, 0.0)
    if same:
        out[0] = 0.0
    return out


def fft_correlate(x, y=None, operation="scalar_product", max_lag=None, method="auto"):
    """Exact correlation of stored series, averaged over every time origin:

        C[k] = 1/(T - k) sum_{t < T-k} op(x[t], y[t + k]),   k = 0 .. max_lag

    x, y : arrays of shape (T, ...) (y defaults to x). operation as in
    :class:`Correlator`; the result has the Correlator's shape: (max_lag + 1, 1)
    for scalar_product, (max_lag + 1, ...) otherwise. method: "auto" (FFTW if
    compiled in, else numpy.fft), "fftw", "numpy" or "direct" (O(T max_lag)
    sum in C++, for checks). Lags are in samples.
    """
    if operation not in _OPERATIONS:
        raise ValueError(f"parameter 'operation' must be one of {', '.join(_OPERATIONS)}; "
                         f"got {operation!r}")
    if method not in ("auto", "fftw", "numpy", "direct"):
        raise ValueError(f"parameter 'method' must be auto, fftw, numpy or direct; got {method!r}")
    if method == "fftw" and not have_fftw():
        raise _marble.FeaturesError("missing feature FFTW (build with MARBLE_WITH_FFTW=ON)")
    xa = np.asarray(x, dtype=float)
    if xa.ndim == 0 or xa.shape[0] == 0 or xa.size == 0:
        raise ValueError("parameter 'x' must have shape (T, ...) with T >= 1")
    shape = xa.shape[1:]
    if method == "numpy" or (method == "auto" and not have_fftw()):
        T = xa.shape[0]
        x2 = xa.reshape(T, -1)
        y2 = x2
        if y is not None:
            ya = np.asarray(y, dtype=float)
            if ya.shape != xa.shape:
                raise ValueError("parameters 'x' and 'y' must have the same shape")
            y2 = ya.reshape(T, -1)
        if not (np.all(np.isfinite(x2)) and np.all(np.isfinite(y2))):
            raise ValueError("parameters 'x', 'y' contain non-finite values")
        lag = T - 1 if max_lag is None else int(max_lag)
        if max_lag is not None and (lag != max_lag or not 0 <= lag < T):
            raise ValueError(f"parameter 'max_lag' must be in [0, {T - 1}], got {max_lag}")
        out = _numpy_correlate(x2, y2, operation, lag)
    else:
        out = _marble.correlate(xa, y, operation, max_lag, method == "direct")
    if operation == "scalar_product":
        return out
    return out.reshape((out.shape[0],) + shape)

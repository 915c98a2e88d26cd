"""rhonn: online identification and adaptive control of nonlinear plants with Recurrent
High-Order Neural Networks, on a Rust core.

The same code as the ``rhonn`` command line, with numpy arrays in and out (SI units)::

    import rhonn
    result = rhonn.run("thesis-ch5")
    result.summary["identification"]
    model = rhonn.fit(u, y, dt=4.0, model="models/cascaded-tanks.toml")
    y_hat = model.predict(u_val, y_val)               # free run, shape (n, p)
    ident = rhonn.OnlineIdentifier(["u"], ["y"], dt=4.0)
    y_est = ident.update(t, u_k, y_k)                 # one sample of your own loop

Errors are ``ValueError`` (a bad argument, scenario or file content), ``OSError`` (a
file that cannot be read or written) or ``RuntimeError`` (a run that failed), with the
command line's message.
"""

from __future__ import annotations

import csv
import json
import os
import tempfile
import warnings as _warnings
from dataclasses import dataclass, field
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _rhonn
from ._rhonn import OnlineIdentifier as _OnlineIdentifier

__version__ = _rhonn.__version__
__all__ = [
    "run",
    "fit",
    "load",
    "campaign",
    "scenarios",
    "show",
    "Model",
    "OnlineIdentifier",
    "RunResult",
]

ArrayLike = Any
PathLike = Union[str, "os.PathLike[str]"]


def _to_pandas(columns: Mapping[str, Any]):
    try:
        import pandas as pd
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("to_pandas() needs pandas: pip install pandas") from e
    return pd.DataFrame(dict(columns))


@dataclass
class RunResult:
    """What ``rhonn.run`` returns.

    Attributes
    ----------
    trajectory : dict of str to numpy.ndarray
        trajectory.csv's columns (SI units: s, Pa, m, A, m^3/s, V), ``t`` first.
    summary : dict
        summary.json's content (figures in display units, the unit in each key).
    validation : dict of str to numpy.ndarray or None
        validation.csv's columns for runs with an identifier.
    """

    trajectory: Dict[str, np.ndarray]
    summary: Dict[str, Any]
    validation: Optional[Dict[str, np.ndarray]] = None
    out: Optional[str] = field(default=None)

    def to_pandas(self):
        """The trajectory as a ``pandas.DataFrame`` (needs pandas)."""
        return _to_pandas(self.trajectory)


def _scenario_args(scenario: Union[str, "os.PathLike[str]", Mapping[str, Any]]):
    """(name, toml_text) for the Rust side."""
    if isinstance(scenario, Mapping):
        name = str(scenario.get("name", "<dict>"))
        return name, _rhonn.json_to_toml(json.dumps(dict(scenario)))
    if isinstance(scenario, (str, os.PathLike)):
        return os.fspath(scenario), None
    raise TypeError(
        f"scenario must be a shipped name, a path to a TOML file or a dict of its tables, not {type(scenario).__name__}"
    )


def run(scenario: Union[str, "os.PathLike[str]", Mapping[str, Any]], *, out: Optional[PathLike] = None) -> RunResult:
    """Run a scenario as ``rhonn run`` does.

    Parameters
    ----------
    scenario : str, path or dict
        A shipped scenario's name (``rhonn.scenarios()``), a path to a TOML file, or a dict
        of the TOML's tables (as ``tomllib.loads(rhonn.show(name))`` gives).
    out : str or path, optional
        Also write the run's folder there, as ``rhonn run --out`` does (the same writer:
        CSV, JSON, SVG and report.html, all or nothing; a folder it may not write is refused
        before the run; an earlier run's files this run does not write are removed).

    Returns
    -------
    RunResult
    """
    name, text = _scenario_args(scenario)
    outp = None if out is None else os.fspath(out)
    traj, val, summary = _rhonn.run(name, text, outp)
    return RunResult(trajectory=traj, summary=json.loads(summary), validation=val, out=outp)


def _matrix(name: str, a: ArrayLike) -> np.ndarray:
    """A float64 C-contiguous (n, k) array from ``a`` ((n,) is one column). A masked array
    with any value masked is refused: ``np.asarray`` would read the values under the mask."""
    if np.ma.isMaskedArray(a):
        masked = int(np.ma.getmaskarray(a).sum())
        if masked:
            raise ValueError(
                f"{name} is a masked array with {masked} masked value{'' if masked == 1 else 's'}: rhonn reads every value, "
                f"so fill them ({name}.filled(...)) or drop those rows first"
            )
        a = np.ma.getdata(a)
    arr = np.asarray(a)
    if arr.dtype.kind not in "fiub":
        raise TypeError(f"{name} must hold real numbers, not {arr.dtype}")
    arr = np.ascontiguousarray(arr, dtype=np.float64)
    if arr.ndim == 1:
        arr = arr.reshape(-1, 1)
    if arr.ndim != 2:
        raise ValueError(f"{name} must be 1-D (one signal) or 2-D (samples, signals), not {arr.ndim}-D with shape {arr.shape}")
    if arr.shape[0] == 0:
        raise ValueError(f"{name} is empty: give at least one sample (row)")
    bad = np.argwhere(~np.isfinite(arr))
    if len(bad):
        i, j = bad[0]
        raise ValueError(f"{name}[{i}, {j}] = {arr[i, j]} is not allowed: every value must be finite")
    # As for a CSV cell (the command's limit): larger values overflow when squared.
    big = np.argwhere(np.abs(arr) > 1e150)
    if len(big):
        i, j = big[0]
        raise ValueError(f"{name}[{i}, {j}] = {arr[i, j]} is not allowed: a magnitude at most 1e150 (larger values overflow when squared: rescale)")
    return arr


def _recordings(name: str, a: Union[ArrayLike, Sequence[ArrayLike]]) -> List[np.ndarray]:
    if isinstance(a, (list, tuple)) and len(a) > 0 and all(np.ndim(x) >= 1 and not np.isscalar(x) for x in a) and any(
        isinstance(x, np.ndarray) for x in a
    ):
        return [_matrix(f"{name}[{k}]", x) for k, x in enumerate(a)]
    return [_matrix(name, a)]


def _names(given: Optional[Sequence[str]], n: int, prefix: str, arg: str) -> List[str]:
    if given is None:
        return [prefix] if n == 1 else [f"{prefix}{k}" for k in range(n)]
    names = [str(x) for x in given]
    if len(names) != n:
        raise ValueError(f"{arg} names {len(names)} signals but the arrays have {n} columns")
    if len(set(names)) != len(names):
        raise ValueError(f"{arg} = {names} repeats a name: give each signal its own")
    return names


def _check_finite_dict(d, at: str) -> None:
    """A NaN or infinity in a dict spec, named by its key (JSON, and TOML's reader after
    it, would only say that the text is not valid)."""
    if isinstance(d, Mapping):
        for k, v in d.items():
            _check_finite_dict(v, f"{at}[{k!r}]")
    elif isinstance(d, (list, tuple)):
        for i, v in enumerate(d):
            _check_finite_dict(v, f"{at}[{i}]")
    elif isinstance(d, float) and not np.isfinite(d):
        raise ValueError(f"{at} = {d} is not allowed: every number of a model spec must be finite")


def _spec_text(model, arg: str = "model"):
    """(toml_text, source) of a model spec given as None, a path or a dict."""
    if model is None:
        return None, "the default model"
    if isinstance(model, Mapping):
        _check_finite_dict(model, arg)
        return _rhonn.json_to_toml(json.dumps(dict(model))), f"{arg} (dict)"
    if isinstance(model, (str, os.PathLike)):
        path = os.fspath(model)
        try:
            with open(path, encoding="utf-8") as f:
                return f.read(), path
        except OSError as e:
            raise OSError(f"cannot read {path}: {e.strerror}") from e
    raise TypeError(f"{arg} must be None, a path to a TOML file or a dict, not {type(model).__name__}")


def fit(
    u: Union[ArrayLike, Sequence[ArrayLike]],
    y: Union[ArrayLike, Sequence[ArrayLike]],
    dt: float,
    *,
    model: Union[None, PathLike, Mapping[str, Any]] = None,
    inputs: Optional[Sequence[str]] = None,
    outputs: Optional[Sequence[str]] = None,
    select: Optional[str] = None,
    select_steps_ahead: Optional[int] = None,
    budget: Optional[float] = None,
) -> Model:
    """Fit a model to recordings, as ``rhonn fit`` does (beside an ARX baseline).

    Parameters
    ----------
    u : array_like of shape (n, m) or (n,), or a list of such arrays
        Inputs, one row per sample (a list: one array per recording).
    y : array_like of shape (n, p) or (n,), or a list of such arrays
        Measured outputs, as ``u``.
    dt : float
        Sample time [s].
    model : str, path or dict, optional
        The structure (a model spec TOML such as ``models/cascaded-tanks.toml``, or a dict
        of its keys); None: the default.
    inputs, outputs : sequence of str, optional
        Signal names (default ``u``/``u0, u1, ...`` and ``y``/``y0, ...``).
    select : "auto" or "none", optional
        ``"auto"``: choose the structure by cross-validation on the recordings
        (``summary["selection"]`` says what was chosen and how it compares with the best
        ARX; the choice may be an ensemble, the mean of the best 2 or 3 candidates, whose
        members ``summary["members"]`` lists); ``"none"``: the fixed default structure. None (the default): ``"auto"``
        when no ``model`` is given, as ``rhonn fit`` without ``--model`` does.
    select_steps_ahead : int, optional
        With the selection: judge the candidates K samples ahead instead of in free run
        (``--select-steps-ahead K``).
    budget : float, optional
        With the selection: the work budget per candidate as a multiple of the default
        (default 1; ``--budget``): a candidate whose estimated work on the folds, from the
        data's size, exceeds it is skipped. Never the clock: the model is the same on
        every machine.

    Returns
    -------
    Model
        ``.predict(u, y, steps_ahead=None)``, ``.save(path)``, ``.summary``.
    """
    us, ys = _recordings("u", u), _recordings("y", y)
    if len(us) != len(ys):
        raise ValueError(f"u has {len(us)} recordings and y {len(ys)}: give one of each per recording")
    for k, (a, b) in enumerate(zip(us, ys)):
        if a.shape[0] != b.shape[0]:
            raise ValueError(f"recording {k}: u has {a.shape[0]} rows and y {b.shape[0]}: give one row per sample in both")
        if a.shape[1] != us[0].shape[1] or b.shape[1] != ys[0].shape[1]:
            raise ValueError(f"recording {k} has other columns than recording 0")
    if not isinstance(dt, (int, float, np.floating, np.integer)) or isinstance(dt, bool):
        raise TypeError(f"dt must be a number of seconds, not {type(dt).__name__}")
    ins = _names(inputs, us[0].shape[1], "u", "inputs")
    outs = _names(outputs, ys[0].shape[1], "y", "outputs")
    # Types here; the rules on the values (which combinations, which ranges) are the
    # command line's, in rhonn_app::fit_args.
    if select is not None and not isinstance(select, str):
        raise TypeError(f"select must be \"auto\", \"none\" or None, not {type(select).__name__}")
    if select_steps_ahead is not None:
        if isinstance(select_steps_ahead, bool) or not isinstance(select_steps_ahead, (int, np.integer)):
            raise TypeError(f"select_steps_ahead must be an int K >= 1 or None, not {type(select_steps_ahead).__name__}")
        select_steps_ahead = max(min(int(select_steps_ahead), 2**120), -(2**120))
    if budget is not None:
        if isinstance(budget, bool) or not isinstance(budget, (int, float, np.integer, np.floating)):
            raise TypeError(f"budget must be a number (a multiple of the default work budget), not {type(budget).__name__}")
        budget = float(budget)
    text, source = _spec_text(model)
    spec = None if text is None else (text, source)
    return Model(_rhonn.fit(us, ys, float(dt), ins, outs, spec, (select, select_steps_ahead, budget)))


def _optional_int(value, arg: str, letter: str) -> Optional[int]:
    """An int or None (`arg`'s value); the rules on its value are the library's
    (rhonn_sysid::prediction_options). Beyond +-2**120 it is clamped (still refused there)."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{arg} must be an int {letter} >= 1 or None, not {type(value).__name__}")
    return max(min(int(value), 2**120), -(2**120))


def _window(init_window) -> Optional[int]:
    return _optional_int(init_window, "init_window", "N")


def _steps(steps_ahead) -> Optional[int]:
    return _optional_int(steps_ahead, "steps_ahead", "K")


def _count(n, arg: str) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
        raise TypeError(f"{arg} must be an int or None, not {type(n).__name__}")
    if n < 4:
        raise ValueError(f"{arg} = {n} is not allowed: give the stream's length, at least 4 samples, or None")
    return int(n)


class Model:
    """A model of recordings: from ``rhonn.fit``, ``rhonn.load`` or
    ``OnlineIdentifier.freeze()``; the same ``model.json`` as the command line.

    Attributes
    ----------
    kind : str
        ``"fit"`` or ``"online-rhonn"``.
    inputs, outputs : list of str
        Signal names, in column order of ``u`` and ``y``.
    sample_time_s : float
        The sample time the model runs at [s].
    summary : dict or None
        ``rhonn.fit``'s summary.json (training figures, the ARX baseline's, the selection);
        None for a loaded or online model.
    warnings : list of str
        What the user must know (data checks, the selection's warnings).

    Methods
    -------
    predict(u, y, steps_ahead=None, baseline=False, init_window=None)
        Free run or K steps ahead; ``baseline=True``: the ARX baseline's.
    score(u, y, steps_ahead=None, baseline=False, init_window=None)
        The figures ``rhonn predict`` gives.
    save(path), to_json()
        The command's ``model.json``.
    """

    def __init__(self, inner: "_rhonn.Model"):
        if not isinstance(inner, _rhonn.Model):
            raise TypeError("Model is made by rhonn.fit, rhonn.load or OnlineIdentifier.freeze()")
        self._inner = inner

    def predict(
        self,
        u: ArrayLike,
        y: ArrayLike,
        steps_ahead: Optional[int] = None,
        baseline: bool = False,
        init_window: Optional[int] = None,
    ) -> np.ndarray:
        """Predict the outputs: free run (``steps_ahead=None``) or K steps ahead.

        Parameters
        ----------
        u : array_like of shape (n, m) or (n,)
            Inputs, sampled at the model's ``sample_time_s``.
        y : array_like of shape (n, p) or (n,)
            Measured outputs (a free run uses only the first samples).
        steps_ahead : int, optional
            K >= 1, or None for a free run.
        baseline : bool
            True: the prediction of the model's ARX baseline instead (``rhonn predict``'s
            ``<y>_hat_arx`` column; the selection's best ARX on the folds, or the ARX with
            the same lags). A model without one (online) raises ``ValueError``.
        init_window : int, optional
            N >= 1: a free run that sees only the first N rows of ``y`` (a benchmark's
            state-initialisation window, ``rhonn predict --init-window N``); a model that
            needs more past outputs gets the first row held before the data.

        Returns
        -------
        numpy.ndarray of shape (n, p)
            Samples before the first prediction repeat ``y``.

        Warns
        -----
        UserWarning
            An input of ``u`` goes beyond its training range by more than a tenth of that
            range (the model extrapolates there), as ``rhonn predict`` warns.
        """
        out, _, said = self._inner._predict(
            _matrix("u", u), _matrix("y", y), _steps(steps_ahead), bool(baseline), _window(init_window)
        )
        for w in said:
            _warnings.warn(w, UserWarning, stacklevel=2)
        return out

    def score(
        self,
        u: ArrayLike,
        y: ArrayLike,
        steps_ahead: Optional[int] = None,
        baseline: bool = False,
        init_window: Optional[int] = None,
    ) -> List[Dict[str, Any]]:
        """The figures ``rhonn predict`` gives for the same data and horizon (``baseline=True``:
        its ARX baseline's figures).

        Returns
        -------
        list of dict
            Per output: ``output``, ``rms_error`` (output units), ``fit_percent``
            (100 (1 - |y - y_hat| / |y - mean y|)), ``nrmse``, ``samples`` (those scored:
            from the first predicted sample on; with ``init_window`` N, from row N on).
        """
        return json.loads(
            self._inner._predict(
                _matrix("u", u), _matrix("y", y), _steps(steps_ahead), bool(baseline), _window(init_window)
            )[1]
        )

    def save(self, path: PathLike, *, force: bool = False) -> None:
        """Write ``model.json`` (read by ``rhonn predict`` and ``rhonn.load``), whole or not
        at all. A different file already at ``path`` is replaced only with ``force=True``
        (else ``OSError``), as ``rhonn fit --force``."""
        self._inner.save(os.fspath(path), bool(force))

    def to_json(self) -> str:
        """The model as model.json's text."""
        return self._inner.to_json()

    @property
    def summary(self) -> Optional[Dict[str, Any]]:
        """The fit's summary.json as a dict (None for a loaded or online model)."""
        s = self._inner._info[4]
        return None if s is None else json.loads(s)

    @property
    def warnings(self) -> List[str]:
        """What the user must know, as ``rhonn fit`` prints it after ``warning:``: the data
        checks (a record sampled far faster than it moves, ...) and the selection's
        warnings (every structure worse than the mean on the folds). What the selection
        found is in ``summary["selection"]["findings"]``."""
        return list(self._inner._info[5])

    @property
    def kind(self) -> str:
        """``"fit"`` or ``"online-rhonn"``."""
        return self._inner._info[0]

    @property
    def inputs(self) -> List[str]:
        """Input names."""
        return list(self._inner._info[1])

    @property
    def outputs(self) -> List[str]:
        """Output names."""
        return list(self._inner._info[2])

    @property
    def sample_time_s(self) -> float:
        """Sample time [s]."""
        return self._inner._info[3]

    def __repr__(self) -> str:
        return f"Model(kind={self.kind!r}, inputs={self.inputs!r}, outputs={self.outputs!r}, sample_time_s={self.sample_time_s})"


def load(path: PathLike) -> Model:
    """Read a ``model.json`` written by ``rhonn fit``, ``rhonn identify``,
    ``rhonn benchmark`` (``DIR/NAME/model.json``, ``DIR/NAME/online/model.json``) or
    ``Model.save``.

    Parameters
    ----------
    path : str or path
        The file.

    Returns
    -------
    Model
        ``kind`` is ``"fit"`` (an offline model, with its ARX baseline when it has one) or
        ``"online-rhonn"`` (a frozen online model). ``summary`` is None: a loaded model
        carries no training figures.

    Raises
    ------
    OSError
        The file cannot be read (the message says why: missing, a folder, no permission).
    ValueError
        It is not JSON, or not a valid model (the field and the value are named).

    Examples
    --------
    >>> m = rhonn.load("out/fit/model.json")
    >>> y_hat = m.predict(u_val, y_val)            # free run, as ``rhonn predict``
    """
    return Model(_rhonn.load(os.fspath(path)))


class OnlineIdentifier(_OnlineIdentifier):
    """Online RHONN identification, one sample at a time (``rhonn identify``'s identifier).

    Without ``model`` it picks its model online as ``rhonn identify`` does: a bank of
    candidates (recursive ARX, lagged RHONNs by recursive least squares, the
    continuous-time neurons, for one input and one output ``rhonn fit``'s
    Wiener-Hammerstein block structures fitted on the warm-up, and the cascade for one
    output and at most 5,000 samples)
    learns the same stream; each is normalised by the warm-up window (the stream's first
    half) and judged by its prequential free-run error; ``update`` returns the leader's
    estimate (during the warm-up: the last measurement), ``selection`` lists every
    candidate's figures, and ``freeze()`` keeps the winner. Fed the records
    ``rhonn identify --epochs 1`` learns (``reset()`` between records) with
    ``samples`` their total length, it gives the command's selection and model.

    A sensor glitch does not poison it: a value more than 100 ranges beyond the range seen
    so far (after 20 samples) is skipped, not learned, and the lags restart after it (3
    such samples in a row are a new range, learned); a step in ``t`` longer than 3 sample
    times restarts the lags instead of learning across the gap; values beyond 1e150 raise
    ``ValueError`` (as in files). ``notes`` says what was skipped, as ``rhonn identify``
    does for a file.

    Parameters
    ----------
    inputs, outputs : sequence of str
        Signal names.
    dt : float
        Sample time [s].
    model : str, path or dict, optional
        None: choose online (above). Else the settings: ``{}`` for the defaults, the
        continuous-time neurons (``models/tanks-online.toml``'s keys: law, gain, degree, filters_s, ...;
        or ``{"structure": "lagged", "lags": {"na": 3, "nb": 2}}``: a lagged RHONN learned
        by recursive least squares, ``models/tanks-online-lagged.toml``; or
        ``{"structure": "cascade", "epochs": 4}``: the continuous-time cascade with a
        hidden neuron learned by extended Kalman filters, one output,
        ``models/tanks-online-cascade.toml``; or ``{"structure": "wiener-hammerstein",
        "block": {"poles": 2, "degree": 3, "window": 600}}``: ``rhonn fit``'s block
        structure fitted on the first ``window`` samples, then learned on by recursive least
        squares, one input and one output; ``freeze()`` before the window is full raises
        ``ValueError``).
    y_offset, y_scale, u_offset, u_scale : sequence of float, optional
        The identifier sees ``(signal - offset) / scale``.
    y_bounds : sequence of (low, high), optional
        Per output, the range its estimate is held in (as ``rhonn identify`` sets from
        the records' range and ``output_margin``). Offsets, scales and bounds need a
        model: choosing online, the warm-up window sets them.
    samples : int, optional
        Choosing online: the stream's length, which sets the warm-up (its first half),
        the free-run window (a tenth, within [20, 5000]) and the scored part (its second
        half). None: as for 2,000 samples.

    Examples
    --------
    >>> ident = rhonn.OnlineIdentifier(["u"], ["y"], dt=4.0, samples=1024)
    >>> y_est = ident.update(0.0, [3.2], [5.2])
    """

    def __new__(
        cls,
        inputs,
        outputs,
        dt,
        model=None,
        y_offset=None,
        y_scale=None,
        u_offset=None,
        u_scale=None,
        y_bounds=None,
        samples=None,
    ):
        for arg, names in (("inputs", inputs), ("outputs", outputs)):
            if isinstance(names, str):
                raise TypeError(f"{arg} must be a sequence of names, e.g. [{names!r}], not the string {names!r}")
        text, _ = _spec_text(model)
        return super().__new__(
            cls,
            [str(x) for x in inputs],
            [str(x) for x in outputs],
            float(dt),
            text,
            None if y_offset is None else [float(v) for v in y_offset],
            None if y_scale is None else [float(v) for v in y_scale],
            None if u_offset is None else [float(v) for v in u_offset],
            None if u_scale is None else [float(v) for v in u_scale],
            None if y_bounds is None else [(float(lo), float(hi)) for lo, hi in y_bounds],
            None if samples is None else _count(samples, "samples"),
        )

    def freeze(self) -> Model:
        """Stop adapting; return the frozen model (``predict``, ``save``). Choosing
        online: the winner so far, which the identifier then is."""
        return Model(super().freeze())

    @property
    def selection(self) -> Optional[Dict[str, Any]]:
        """Choosing online (no model, before ``freeze()``): every candidate's prequential
        figures and the winner so far, as ``rhonn identify``'s ``selection`` in
        summary.json; None otherwise."""
        text = self._selection_json
        return None if text is None else json.loads(text)


def _read_table(path: str) -> Dict[str, np.ndarray]:
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    table: Dict[str, np.ndarray] = {}
    for j, name in enumerate(header):
        col = [r[j] for r in body]
        try:
            table[name] = np.array([float(v) if v != "" else np.nan for v in col], dtype=np.float64)
        except ValueError:
            table[name] = np.array(col, dtype=object)
    return table


class CampaignTable(dict):
    """runs.csv of a campaign as a dict of column name -> array (``.to_pandas()``)."""

    out: str = ""

    def to_pandas(self):
        """The table as a ``pandas.DataFrame`` (needs pandas)."""
        return _to_pandas(self)


def campaign(
    scenario: Union[str, "os.PathLike[str]", Mapping[str, Any]],
    runs: int = 100,
    seed: int = 0,
    threads: Optional[int] = None,
    *,
    out: Optional[PathLike] = None,
    corners: bool = False,
) -> CampaignTable:
    """A Monte Carlo campaign over the scenario's tolerances, as ``rhonn campaign`` does.

    Parameters
    ----------
    scenario : str, path or dict
        As for ``run``.
    runs : int
        Number of runs (ignored with ``corners=True``: every corner once).
    seed : int
        The campaign's seed (runs are reproducible from it).
    threads : int, optional
        Worker threads (None: every core).
    out : str or path, optional
        The campaign's folder (runs.csv, summary.json, plots); a folder left by an
        interrupted campaign is resumed. None: a temporary folder, removed afterwards.

    Returns
    -------
    CampaignTable
        runs.csv's columns: ``run``, the drawn parameters, ``status``, the figures.
    """
    for arg, v, lo, hi in (("runs", runs, 1, 10_000_000), ("seed", seed, 0, 2**64 - 1)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not lo <= v <= hi:
            raise ValueError(f"{arg} = {v!r} is not allowed: give an int in [{lo}, {hi}]")
    if threads is not None and (isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or threads < 1):
        raise ValueError(f"threads = {threads!r} is not allowed: give an int >= 1, or None for every core")
    name, text = _scenario_args(scenario)

    def go(folder: str) -> CampaignTable:
        d = _rhonn.campaign(name, int(runs), int(seed), folder, text, threads, bool(corners))
        t = CampaignTable(_read_table(os.path.join(d, "runs.csv")))
        t.out = d
        return t

    if out is not None:
        return go(os.fspath(out))
    with tempfile.TemporaryDirectory(prefix="rhonn-campaign-") as tmp:
        t = go(os.path.join(tmp, "campaign"))
        t.out = ""
        return t


def scenarios() -> Dict[str, str]:
    """The shipped scenarios: name -> one-line description."""
    return dict(_rhonn.scenarios())


def show(scenario: str) -> str:
    """A scenario's TOML text (copy it to start your own)."""
    return _rhonn.show(scenario)

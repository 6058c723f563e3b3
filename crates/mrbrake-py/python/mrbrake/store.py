"""The results store of design studies: the SQLite file that ``mrbrake sweep`` and
``mrbrake optimize`` write (one record per design, keyed by its design hash)."""

import math

from . import _native

__all__ = ["load", "records"]

_NON_FINITE = {"NaN": math.nan, "inf": math.inf, "-inf": -math.inf}


def records(path):
    """Every record of the store at ``path`` as ``mrbrake export STORE --json`` lists them:
    ``{key, status, reason, variables: {name: value}, metrics: {name: value}, metric_bounds:
    {name: bound}, settings: {name: value}, eval_seconds, solver_version}`` (a metric beyond the
    analysed range is ``None`` with its bound in ``metric_bounds``: ``{"at_least": x}``,
    ``{"at_most": x}`` or ``{"not_applicable": True}``) (``settings``: the evaluation settings, e.g.
    ``mesh_level``, ``element_order``, ``speed_rad_s``; empty for records of older stores); variables and metrics in SI (metric names carry their unit), non-finite
    values as the strings ``"NaN"``, ``"inf"``, ``"-inf"``. Opened read-only."""
    return _native.store_records(str(path))


def _number(value):
    return _NON_FINITE.get(value, value) if isinstance(value, str) else value


def _bound_text(bound):
    if "at_least" in bound:
        return f">={_number(bound['at_least'])}"
    if "at_most" in bound:
        return f"<={_number(bound['at_most'])}"
    return "n/a"


def load(path):
    """The store at ``path`` as a table, one row per design: ``key``, ``status``, ``reason``,
    then a column per variable, per metric and per evaluation setting (SI, NaN where a record
    lacks one or has a bound beyond the analysed range), a column ``<metric>_beyond`` per metric
    with such a bound (``">=x"``, ``"<=x"`` or ``"n/a"``, as in ``mrbrake export``), then
    ``eval_seconds`` and ``solver_version``. A pandas DataFrame when pandas is installed, a list
    of dicts (the rows) otherwise."""
    rows = []
    for r in records(path):
        row = {"key": r["key"], "status": r["status"], "reason": r["reason"]}
        row.update({k: _number(v) for k, v in r["variables"].items()})
        row.update({k: math.nan if v is None else _number(v) for k, v in r["metrics"].items()})
        row.update({f"{k}_beyond": _bound_text(b) for k, b in r.get("metric_bounds", {}).items()})
        row.update(r.get("settings", {}))
        row["eval_seconds"] = _number(r["eval_seconds"])
        row["solver_version"] = r["solver_version"]
        rows.append(row)
    try:
        import pandas
    except ImportError:
        return rows
    return pandas.DataFrame(rows)

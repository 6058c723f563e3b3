"""The results store of design studies: the SQLite file that ``mrbrake sweep`` and
``mrbrake optimize`` write (one record per design, keyed by its design hash)."""

import math

from . import _native

__all__ = ["load", "records"]

_NON_FINITE = {"NaN": math.nan, "inf": math.inf, "-inf": -math.inf}


def records(path):
    """Every record of the store at ``path`` as ``mrbrake export STORE --json`` lists them:
    ``{key, status, reason, variables: {name: value}, metrics: {name: value}, settings: {name:
    value}, eval_seconds, solver_version}`` (``settings``: the evaluation settings, e.g.
    ``mesh_level``, ``element_order``, ``speed_rad_s``; empty for records of older stores); variables and metrics in SI (metric names carry their unit), non-finite
    values as the strings ``"NaN"``, ``"inf"``, ``"-inf"``. Opened read-only."""
    return _native.store_records(str(path))


def _number(value):
    return _NON_FINITE.get(value, value) if isinstance(value, str) else value


def load(path):
    """The store at ``path`` as a table, one row per design: ``key``, ``status``, ``reason``,
    then a column per variable, per metric and per evaluation setting (SI, NaN where a record
    lacks one), then ``eval_seconds`` and ``solver_version``. A pandas DataFrame when pandas is installed, a list
    of dicts (the rows) otherwise."""
    rows = []
    for r in records(path):
        row = {"key": r["key"], "status": r["status"], "reason": r["reason"]}
        row.update({k: _number(v) for k, v in r["variables"].items()})
        row.update({k: _number(v) for k, v in r["metrics"].items()})
        row.update(r.get("settings", {}))
        row["eval_seconds"] = _number(r["eval_seconds"])
        row["solver_version"] = r["solver_version"]
        rows.append(row)
    try:
        import pandas
    except ImportError:
        return rows
    return pandas.DataFrame(rows)

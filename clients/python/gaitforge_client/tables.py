"""Protobuf messages as plain dicts (field names as in the proto), or pandas DataFrames.

An invalid evaluation has fitness None, never a number (issue 24: invalid is not 0).
"""
import math

from .errors import GaitforgeError


def fields(msg):
    """Every scalar and repeated field of `msg`; sub-messages left to the caller."""
    out = {}
    for f in msg.DESCRIPTOR.fields:
        value = getattr(msg, f.name)
        if f.message_type is None:
            out[f.name] = list(value) if f.label == f.LABEL_REPEATED else value
    return out


def individual(ind):
    row = {k: v for k, v in fields(ind).items()}
    ev = ind.evaluation
    row["valid"] = ev.valid
    row["fitness"] = ev.fitness if ev.valid else None
    row["reason"] = ev.reason
    row["metrics"] = dict(ev.metrics)
    return row


def hof_entry(entry):
    row = {"rank": entry.rank}
    row.update(individual(entry.individual))
    for unused in ("reason", "metrics", "worker_id", "eval_seconds", "carried", "violation"):
        row.pop(unused, None)
    return row


def summary(s):
    row = fields(s)
    row["state"] = state_name(s)
    if math.isnan(row["best_fitness"]):
        row["best_fitness"] = None
    row["spec"] = s.spec
    return row


def state_name(msg):
    """'running', 'interrupted', ... : the word of `msg`'s state enum, as the proto names it
    (STUDY_STATE_RUNNING, DIAGNOSIS_STATE_RUNNING -> running)."""
    enum = msg.DESCRIPTOR.fields_by_name["state"].enum_type
    value = enum.values_by_number.get(msg.state)
    return value.name.split("STATE_", 1)[1].lower() if value else str(msg.state)


def table(rows, as_dataframe):
    """`rows` as they are, or as a pandas DataFrame (pandas must be importable)."""
    if not as_dataframe:
        return rows
    try:
        import pandas
    except ImportError as e:
        raise GaitforgeError("as_dataframe=True needs pandas (Debian: python3-pandas)") from e
    return pandas.DataFrame(rows)

"""Stored diagnoses (docs/diagnosis.md, "Stored diagnoses"): specs as dicts or files, and
the summaries and reports the coordinator keeps."""
import copy
import json
import os

from . import spec as specs
from . import tables

def read_spec(spec, upload):
    """A DiagnosisSpec dict from a dict or a YAML/JSON file; a file's training and held_out
    recordings named by path (relative to its folder) are uploaded and named by hash."""
    if isinstance(spec, dict):
        return copy.deepcopy(spec), os.getcwd()
    path = os.fspath(spec)
    data = specs.read_file(path)
    base = os.path.dirname(os.path.abspath(path))
    for key in ("training", "held_out"):
        entries = data.get(key)
        if isinstance(entries, list):
            data[key] = [e if not isinstance(e, str) or specs.is_hash(e) or not e
                         else upload(os.path.join(base, e)) for e in entries]
    return data, base


def summary(s):
    """A DiagnosisSummary as a dict: state as a word, the spec as a dict."""
    row = tables.fields(s)
    row["state"] = tables.state_name(s)
    row["spec"] = json_spec(s.spec)
    return row


def json_spec(message):
    from google.protobuf import json_format
    return json_format.MessageToDict(message, preserving_proto_field_name=True)


def with_report(reply, files_dir):
    """GetDiagnosisResponse as a dict: the summary, `report` (the parsed diagnosis.json, or
    None before it completes) and `files` (names; written to files_dir when given)."""
    row = summary(reply.diagnosis)
    row["report"] = json.loads(reply.report_json) if reply.report_json else None
    row["files"] = [f.name for f in reply.files]
    if files_dir and reply.files:
        os.makedirs(files_dir, exist_ok=True)
        for f in reply.files:
            with open(os.path.join(files_dir, f.name), "wb") as out:
                out.write(f.content)
    return row

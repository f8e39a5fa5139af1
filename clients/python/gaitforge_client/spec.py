"""Study specs for CreateStudy: a dict, or a YAML/JSON file (docs/spec.md).

The coordinator applies defaults and validates (its messages name the field). The client
only maps keys onto StudySpec (an unknown key is InvalidSpec naming it) and, for a spec
file, uploads the recordings it names by path, relative to the file's folder, as
`gaitforge submit` does. A robot given as a descriptor file or robot folder
(objective.robot, docs/robots.md) is read as the CLI reads it: the spec then carries the
robot's name and the descriptor's text, which the coordinator checks.
"""
import copy
import os
import re

from google.protobuf import json_format

from .errors import InvalidSpec, NotFound

_HASH = re.compile(r"^[0-9a-f]{64}$")
_NO_FIELD = re.compile(r'has no field named "([^"]+)"')
_PARENT = re.compile(r"Failed to parse (\w+) field")
_KNOWN = re.compile(r"Available Fields\(except extensions\): \"\[(.*)\]\"")


def read_file(path):
    """The spec file's mapping; NotFound when it cannot be read, InvalidSpec when it does not parse."""
    import yaml
    if os.path.isdir(path):
        raise InvalidSpec(f"{path}: is a directory, not a spec file")
    try:
        with open(path, encoding="utf-8") as f:
            data = yaml.safe_load(f)
    except OSError as e:
        raise NotFound(f"{path}: {e.strerror}") from e
    except yaml.YAMLError as e:
        raise InvalidSpec(f"{path}: {e}") from e
    if not isinstance(data, dict):
        raise InvalidSpec(f"{path}: expected a mapping of spec fields")
    return data


def looks_like_robot_path(robot, base_dir):
    """True when objective.robot names a file or folder rather than a built-in robot."""
    return isinstance(robot, str) and robot != "" and (
        "/" in robot or robot.endswith((".yaml", ".json")) or
        os.path.exists(os.path.join(base_dir, robot)))


def with_robot_descriptor(data, base_dir):
    """A copy of `data` whose objective.robot path is replaced by the robot's name, with the
    descriptor's text in objective.robot_descriptor; NotFound when the file is missing."""
    objective = (data.get("objective") or {})
    robot = objective.get("robot", "")
    if objective.get("robot_descriptor") or not looks_like_robot_path(robot, base_dir):
        return data
    import yaml
    path = os.path.join(base_dir, robot)
    if os.path.isdir(path):
        path = os.path.join(path, "robot.yaml")
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        raise NotFound(f"field 'objective.robot': cannot open '{path}': {e.strerror}") from e
    try:
        name = (yaml.safe_load(text) or {}).get("name", "")
    except (yaml.YAMLError, AttributeError) as e:
        raise InvalidSpec(f"field 'objective.robot': {path}: not a robot descriptor: {e}") from e
    data = copy.deepcopy(data)
    data["objective"]["robot"] = name if isinstance(name, str) else ""
    data["objective"]["robot_descriptor"] = text
    return data


def to_message(data, spec_type):
    """`data` (a dict of spec fields) as a StudySpec; InvalidSpec naming an unknown or ill-typed field."""
    try:
        return json_format.ParseDict(data, spec_type())
    except json_format.ParseError as e:
        raise InvalidSpec(_parse_error(str(e))) from e


def _parse_error(text):
    """ParseDict's message as `field 'PATH': WHAT`, like the CLI's spec errors."""
    parents = _PARENT.findall(text)
    leaf = _NO_FIELD.search(text)
    path = ".".join(parents + ([leaf.group(1)] if leaf else [])) or "spec"
    known = _KNOWN.search(text)
    if leaf:
        what = f"unknown field '{leaf.group(1)}'" + (f" (known: {_names(known.group(1))})" if known else "")
    else:
        what = " ".join(text.split())
    return f"field '{path}': {what}"


def _names(listed):
    """"'name', 'heldOut'" (protobuf's JSON names) as "name, held_out" (the spec's)."""
    names = [n.strip().strip("'") for n in listed.split(",")]
    return ", ".join(re.sub(r"[A-Z]", lambda m: "_" + m.group(0).lower(), n) for n in names)


def is_hash(text):
    """True for a recording's content hash (64 lowercase hex digits)."""
    return bool(_HASH.match(text))


def with_uploaded_recordings(data, base_dir, upload):
    """A copy of `data` whose recording paths are replaced by the hashes `upload(path)` returns."""
    data = copy.deepcopy(data)
    objective = data.get("objective") or {}
    for key in ("recordings", "held_out"):
        entries = objective.get(key)
        if not isinstance(entries, list):
            continue
        objective[key] = [e if not isinstance(e, str) or is_hash(e) or not e
                          else upload(os.path.join(base_dir, e)) for e in entries]
    return data

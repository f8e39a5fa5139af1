"""Errors of the Python client, one class per exit code of the CLI (docs/cli.md).

Every failed call raises a GaitforgeError subclass, never a bare grpc.RpcError:
`exit_code` is the code `gaitforge` would exit with for the same failure.
"""
import re

import grpc


class GaitforgeError(Exception):
    """Any failure; `exit_code` as the CLI's, `grpc_code` when it came from a call."""

    exit_code = 5

    def __init__(self, message, grpc_code=None):
        super().__init__(message)
        self.message = message
        self.grpc_code = grpc_code


class StudyNotCompleted(GaitforgeError):
    """A watched study ended failed or cancelled (exit 1); `progress` is its last Progress."""

    exit_code = 1

    def __init__(self, message, progress=None):
        super().__init__(message)
        self.progress = progress


class InvalidRequest(GaitforgeError):
    """INVALID_ARGUMENT or FAILED_PRECONDITION (exit 2)."""

    exit_code = 2


class InvalidSpec(InvalidRequest):
    """A spec the client or coordinator refused. `field` is the first problem's field path
    (e.g. 'population'), `problems` every (field, message) pair, one per line of the reply."""

    def __init__(self, message, grpc_code=None):
        super().__init__(message, grpc_code)
        self.problems = [(_field_of(line), line) for line in message.splitlines() if line.strip()]
        self.field = self.problems[0][0] if self.problems else None


class NotFound(GaitforgeError):
    """NOT_FOUND or OUT_OF_RANGE: unknown study, generation or rank; a missing file (exit 3)."""

    exit_code = 3


class Unavailable(GaitforgeError):
    """UNAVAILABLE or DEADLINE_EXCEEDED; a local coordinator that did not start (exit 4)."""

    exit_code = 4


class Denied(GaitforgeError):
    """UNAUTHENTICATED or PERMISSION_DENIED: no, unknown or wrong-role token (exit 6)."""

    exit_code = 6


_FIELD = re.compile(r"field '([^']+)'")

_BY_CODE = {
    grpc.StatusCode.INVALID_ARGUMENT: InvalidRequest,
    grpc.StatusCode.FAILED_PRECONDITION: InvalidRequest,
    grpc.StatusCode.NOT_FOUND: NotFound,
    grpc.StatusCode.OUT_OF_RANGE: NotFound,
    grpc.StatusCode.UNAVAILABLE: Unavailable,
    grpc.StatusCode.DEADLINE_EXCEEDED: Unavailable,
    grpc.StatusCode.UNAUTHENTICATED: Denied,
    grpc.StatusCode.PERMISSION_DENIED: Denied,
}


def _field_of(line):
    m = _FIELD.search(line)
    return m.group(1) if m else None


def from_rpc_error(err, spec_call=False):
    """The GaitforgeError for a grpc.RpcError; INVALID_ARGUMENT of a spec call is InvalidSpec."""
    code = err.code()
    details = err.details() or str(code)
    if spec_call and code == grpc.StatusCode.INVALID_ARGUMENT:
        return InvalidSpec(details, code)
    return _BY_CODE.get(code, GaitforgeError)(details, code)

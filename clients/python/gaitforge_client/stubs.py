"""Finds the generated gRPC stubs (never committed; the CMake build writes them).

Order: the directory in $GAITFORGE_PYTHON_STUBS, else build/python of the source tree this
package sits in. That directory holds gaitforge/v1/*_pb2.py and *_pb2_grpc.py.
"""
import importlib
import os
import sys

from .errors import GaitforgeError

# The source tree this package sits in (clients/python/gaitforge_client/).
SOURCE_TREE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))


def stubs_dir():
    return os.environ.get("GAITFORGE_PYTHON_STUBS") or os.path.join(SOURCE_TREE, "build", "python")


def load(name):
    """Imports gaitforge.v1.<name> from the stubs directory."""
    path = stubs_dir()
    if not os.path.isfile(os.path.join(path, "gaitforge", "v1", "study_pb2.py")):
        raise GaitforgeError(
            f"no generated stubs in {path}: build gaitforge (scripts/build.sh) or set "
            "GAITFORGE_PYTHON_STUBS to the build's python/ directory")
    if path not in sys.path:
        sys.path.insert(0, path)
    return importlib.import_module("gaitforge.v1." + name)

"""Python client of gaitforge (docs/python.md).

    from gaitforge_client import Client
    with Client.local(db="runs/py.db", workers=2) as gf:
        sid = gf.submit("examples/analytic-ga.yaml")
        gf.watch(sid, on_progress=print)
        gf.history(sid, as_dataframe=True)
"""
from .client import Client
from .errors import (Denied, GaitforgeError, InvalidRequest, InvalidSpec, NotFound,
                     StudyNotCompleted, Unavailable)

__all__ = ["Client", "Denied", "GaitforgeError", "InvalidRequest", "InvalidSpec", "NotFound",
           "StudyNotCompleted", "Unavailable"]

"""The gaitforge client: StudyService and RecordingService over gRPC (docs/python.md)."""
import contextlib
import math
import os

import grpc

from . import diagnoses as diag
from . import spec as specs
from . import stubs, tables
from .errors import (GaitforgeError, InvalidRequest, InvalidSpec, NotFound, StudyNotCompleted,
                     Unavailable, from_rpc_error)
from .local import LocalCluster

_MAX_MESSAGE = 64 * 1024 * 1024  # the coordinator's default --max-message-mb


class Client:
    """A connection to a coordinator at `target` (HOST:PORT).

    token: the client-role bearer token (default: $GAITFORGE_TOKEN). tls_ca: a PEM CA file
    to trust; tls_cert and tls_key: a PEM client certificate and key (mutual TLS; system
    roots without tls_ca). TLS is used when any is given, plaintext otherwise. timeout:
    seconds per unary call (watch has none)."""

    def __init__(self, target, token=None, tls_ca=None, timeout=30.0, tls_cert=None, tls_key=None):
        self.target = target
        self.timeout = timeout
        self._pb = stubs.load("study_pb2")
        self._rec_pb = stubs.load("recording_pb2")
        token = token if token is not None else os.environ.get("GAITFORGE_TOKEN", "")
        self._metadata = [("authorization", "Bearer " + token.strip())] if token.strip() else []
        options = [("grpc.max_receive_message_length", _MAX_MESSAGE),
                   ("grpc.max_send_message_length", _MAX_MESSAGE)]
        if tls_ca or tls_cert or tls_key:
            self._channel = grpc.secure_channel(target, _tls(tls_ca, tls_cert, tls_key), options)
        else:
            self._channel = grpc.insecure_channel(target, options)
        self._studies = stubs.load("study_pb2_grpc").StudyServiceStub(self._channel)
        self._recordings = stubs.load("recording_pb2_grpc").RecordingServiceStub(self._channel)
        self._diag_pb = stubs.load("diagnosis_pb2")
        self._diagnoses = stubs.load("diagnosis_pb2_grpc").DiagnosisServiceStub(self._channel)

    @classmethod
    @contextlib.contextmanager
    def local(cls, db="runs/gaitforge.db", workers=1, threads=1, binaries=None):
        """A Client of a private coordinator with `workers` worker processes over `db`,
        stopped when the with-block ends (like `gaitforge local`)."""
        cluster = LocalCluster(db, workers, threads, binaries)
        client = None
        try:
            client = cls(cluster.target)
            client.cluster = cluster
            yield client
        finally:
            if client is not None:
                client.close()
            cluster.close()

    def close(self):
        self._channel.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _call(self, method, request, spec_call=False):
        try:
            return method(request, timeout=self.timeout, metadata=self._metadata)
        except grpc.RpcError as e:
            raise from_rpc_error(e, spec_call) from None

    # -- studies --

    def submit(self, spec):
        """Creates a study from a dict of spec fields or a YAML/JSON spec file; its id."""
        if isinstance(spec, dict):
            return self._create(specs.with_robot_descriptor(spec, os.getcwd()))
        path = os.fspath(spec)
        data = specs.read_file(path)
        base = os.path.dirname(os.path.abspath(path))
        data = specs.with_robot_descriptor(data, base)
        data = specs.with_uploaded_recordings(data, base, self._upload_for_spec)
        try:
            return self._create(data)
        except InvalidSpec as e:
            raise InvalidSpec(f"{path}: {e.message}", e.grpc_code) from None

    def _create(self, data):
        message = specs.to_message(data, self._pb.StudySpec)
        reply = self._call(self._studies.CreateStudy,
                           self._pb.CreateStudyRequest(spec=message), spec_call=True)
        return reply.study.study_id

    def study(self, study_id):
        """The study's summary as a dict (`spec` is the StudySpec message after defaults)."""
        return tables.summary(self._call(self._studies.GetStudy,
                                         self._pb.GetStudyRequest(study_id=study_id)))

    def studies(self, as_dataframe=False):
        """Every study's summary, by creation time."""
        reply = self._call(self._studies.ListStudies, self._pb.ListStudiesRequest())
        return tables.table([tables.summary(s) for s in reply.studies], as_dataframe)

    def watch(self, study_id, on_progress=None):
        """Follows the study to its end, calling on_progress(dict) per Progress message.
        Returns the last progress of a completed study; raises StudyNotCompleted when it
        ends failed or cancelled (the CLI's exit 1), Unavailable when the coordinator goes
        away under the watch (the study's committed generations stay; resume it)."""
        last = None
        try:
            stream = self._studies.WatchStudy(self._pb.WatchStudyRequest(study_id=study_id),
                                              metadata=self._metadata)
            for message in stream:
                last = _progress(message)
                if on_progress is not None:
                    on_progress(last)
        except grpc.RpcError as e:
            lost = e.code() in (grpc.StatusCode.UNAVAILABLE, grpc.StatusCode.CANCELLED)
            if last is None or not lost:  # never reached, or refused: not a lost coordinator
                raise from_rpc_error(e) from None
            raise _lost(study_id, e.details()) from None
        if last is None:
            raise GaitforgeError(f"watch of study {study_id} ended before any progress")
        if last["state"] == "running":
            raise _lost(study_id, "the stream ended while the study ran")
        if last["state"] != "completed":
            why = last["error"] or last["stop_reason"]
            raise StudyNotCompleted(f"study {study_id} ended {last['state']}"
                                    + (f": {why}" if why else ""), last)
        return last

    def history(self, study_id, as_dataframe=False):
        """One row per committed generation (GenerationStats fields)."""
        reply = self._call(self._studies.GetHistory, self._pb.GetHistoryRequest(study_id=study_id))
        rows = [tables.fields(g) for g in reply.generations]
        return tables.table(rows, as_dataframe)

    def hall_of_fame(self, study_id, generation=None, as_dataframe=False):
        """The hall of fame of the latest committed generation (or `generation`), best first:
        rank, generation and member first evaluated, genes, valid, fitness (None if invalid)."""
        request = self._pb.GetHallOfFameRequest(study_id=study_id)
        if generation is not None:
            request.generation = generation
        reply = self._call(self._studies.GetHallOfFame, request)
        return tables.table([tables.hof_entry(e) for e in reply.entries], as_dataframe)

    def individuals(self, study_id, generation, as_dataframe=False):
        """Every stored member of `generation`, by member (fitness None when invalid)."""
        reply = self._call(self._studies.ListIndividuals,
                           self._pb.ListIndividualsRequest(study_id=study_id, generation=generation))
        return tables.table([tables.individual(i) for i in reply.individuals], as_dataframe)

    def validate(self, study_id, members=0, ensemble_seed=0, top=0, gaits=None,
                 from_calibration=""):
        """Creates the validation study of robust study `study_id` (docs/objectives.md,
        "Validation"): its hall-of-fame gaits (the first `top`; 0: all), or `gaits` (lists of
        genes), each over a fresh ensemble of `members` members (0: four times the study's)
        drawn from `ensemble_seed` (0: the study's ensemble seed + 1), with the study's model
        or, given `from_calibration`, that calibration study's. Returns the new study's
        id; `watch` it, then `individuals(id, 0)` gives gait i as member i, its prediction in
        metrics robust.mean."""
        request = {"study_id": study_id, "members": members, "seed": ensemble_seed, "top": top,
                   "from_calibration": from_calibration}
        if gaits is not None:
            request["gaits"] = [{"genes": [float(x) for x in g]} for g in gaits]
        return self._create({"validate": request})

    def resume(self, study_id):
        """Sets a stopped study running again on the coordinator; its summary."""
        return tables.summary(self._call(self._studies.ResumeStudy,
                                         self._pb.ResumeStudyRequest(study_id=study_id)))

    def cancel(self, study_id):
        """Cancels a running study (its stored results stay); its summary."""
        return tables.summary(self._call(self._studies.CancelStudy,
                                         self._pb.CancelStudyRequest(study_id=study_id)))

    # -- recordings --

    def add_recording(self, csv, sidecar=None):
        """Uploads CSV and its JSON sidecar (default CSV + '.json'), like `gaitforge recording
        add`. Returns a dict: hash, name, ..., already_stored, missing_cells."""
        sidecar = sidecar or csv + ".json"
        request = self._rec_pb.AddRecordingRequest(name=os.path.basename(csv), csv=_read(csv),
                                                   sidecar=_read(sidecar))
        reply = self._call(self._recordings.AddRecording, request)
        row = tables.fields(reply.recording)
        row.update(already_stored=reply.already_stored, missing_cells=reply.missing_cells)
        return row

    def recordings(self, as_dataframe=False):
        reply = self._call(self._recordings.ListRecordings, self._rec_pb.ListRecordingsRequest())
        return tables.table([tables.fields(r) for r in reply.recordings], as_dataframe)

    # -- diagnoses --

    def diagnose(self, spec):
        """Starts a diagnosis on the coordinator (a dict of DiagnosisSpec fields, or a YAML/
        JSON file whose recordings are uploaded); its id. The same spec again returns the
        running or completed diagnosis with that spec."""
        data, _ = diag.read_spec(spec, self._upload_for_spec)
        message = specs.to_message(data, self._diag_pb.DiagnosisSpec)
        reply = self._call(self._diagnoses.CreateDiagnosis,
                           self._diag_pb.CreateDiagnosisRequest(spec=message), spec_call=True)
        return reply.diagnosis_id

    def diagnoses(self, as_dataframe=False):
        """Every stored diagnosis's summary, oldest first."""
        reply = self._call(self._diagnoses.ListDiagnoses, self._diag_pb.ListDiagnosesRequest())
        return tables.table([diag.summary(d) for d in reply.diagnoses], as_dataframe)

    def diagnosis(self, diagnosis_id, wait=False, on_progress=None, files_dir=None, poll=0.5):
        """The diagnosis's summary with `report` (diagnosis.json as a dict, once completed)
        and `files`. wait: poll until it ends, calling on_progress(summary) on each change;
        then StudyNotCompleted if it failed or was cancelled. files_dir: write its report and
        figures there."""
        import time
        seen = None
        while True:
            reply = self._call(self._diagnoses.GetDiagnosis,
                               self._diag_pb.GetDiagnosisRequest(diagnosis_id=diagnosis_id))
            row = diag.summary(reply.diagnosis)
            if not wait or row["state"] != "running":
                break
            if on_progress is not None and row["progress"] != seen:
                on_progress(row)
                seen = row["progress"]
            time.sleep(poll)
        if wait and row["state"] in ("failed", "cancelled"):
            raise StudyNotCompleted(f"diagnosis {diagnosis_id} ended {row['state']}"
                                    + (f": {row['error']}" if row["error"] else ""), row)
        reply = self._call(self._diagnoses.GetDiagnosis, self._diag_pb.GetDiagnosisRequest(
            diagnosis_id=diagnosis_id, with_files=row["state"] == "completed"))
        return diag.with_report(reply, files_dir)

    def cancel_diagnosis(self, diagnosis_id):
        """Stops a running diagnosis at its next check; its summary."""
        return diag.summary(self._call(self._diagnoses.CancelDiagnosis,
                                       self._diag_pb.CancelDiagnosisRequest(diagnosis_id=diagnosis_id)))

    def _upload_for_spec(self, path):
        return self.add_recording(path)["hash"]


def _lost(study_id, why):
    return Unavailable(f"lost the coordinator while watching study {study_id} ({why}); its "
                       f"committed generations are stored: resume('{study_id}') continues it")


def _tls(ca, cert, key):
    if bool(cert) != bool(key):
        raise InvalidRequest("tls_cert and tls_key go together")
    return grpc.ssl_channel_credentials(root_certificates=_read(ca), private_key=_read(key),
                                        certificate_chain=_read(cert))


def _read(path):
    if not path:
        return None
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError as e:
        raise NotFound(f"{path}: {e.strerror}") from None


def _progress(message):
    row = tables.fields(message)
    row["state"] = tables.state_name(message)
    for key in ("best", "mean"):
        if math.isnan(row[key]):
            row[key] = None
    return row

-- Schema version 6: diagnoses as stored jobs (docs/diagnosis.md, "Stored diagnoses").
CREATE TABLE diagnoses (
  diagnosis_id TEXT PRIMARY KEY,
  name         TEXT NOT NULL,
  spec         BLOB NOT NULL,        -- serialized gaitforge.v1.DiagnosisSpec (defaults applied)
  state        TEXT NOT NULL,        -- running | completed | failed | cancelled
  verdict      TEXT NOT NULL,        -- found | ambiguous | none, once completed
  error        TEXT NOT NULL,        -- why it failed
  report       TEXT NOT NULL,        -- diagnosis.json, once completed
  created_ms   INTEGER NOT NULL,
  updated_ms   INTEGER NOT NULL
) WITHOUT ROWID;
-- The files a completed diagnosis wrote: its figures, located slices and corrected model.
CREATE TABLE diagnosis_files (
  diagnosis_id TEXT NOT NULL REFERENCES diagnoses(diagnosis_id),
  name         TEXT NOT NULL,
  content      BLOB NOT NULL,
  PRIMARY KEY (diagnosis_id, name)
) WITHOUT ROWID;

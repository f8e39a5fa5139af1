-- gaitforge results database, schema version 1. Documented in docs/storage.md.
-- Fitness is "higher is better"; genes are stored as little-endian IEEE doubles (bit-exact)
-- and, for people using the sqlite3 shell, as JSON text.

CREATE TABLE studies (
  study_id          TEXT PRIMARY KEY,
  name              TEXT NOT NULL,
  spec              BLOB NOT NULL,          -- serialized gaitforge.v1.StudySpec
  spec_json         TEXT NOT NULL,          -- the same spec as JSON, for people
  state             TEXT NOT NULL,          -- running | paused | cancelled | completed | failed
  generations_total INTEGER NOT NULL,
  generations_done  INTEGER NOT NULL DEFAULT 0,
  best_fitness      REAL,
  mean_fitness      REAL,
  evaluations       INTEGER NOT NULL DEFAULT 0,  -- distinct evaluated jobs
  created_ms        INTEGER NOT NULL,       -- Unix milliseconds
  updated_ms        INTEGER NOT NULL,
  error             TEXT NOT NULL DEFAULT ''
);

-- One row per committed generation; engine_state is the engine after Tell() of it.
CREATE TABLE generations (
  study_id      TEXT NOT NULL REFERENCES studies(study_id),
  generation    INTEGER NOT NULL,
  best          REAL,
  mean          REAL,
  stddev        REAL,
  diversity     REAL,
  evaluations   INTEGER NOT NULL,
  invalid       INTEGER NOT NULL,
  committed_ms  INTEGER NOT NULL,
  engine_state  BLOB NOT NULL,
  PRIMARY KEY (study_id, generation)
) WITHOUT ROWID;

-- Every member of every generation. Evaluated members are written as their results arrive
-- (so a restart never evaluates them again); carried members with their generation.
CREATE TABLE individuals (
  study_id          TEXT NOT NULL REFERENCES studies(study_id),
  generation        INTEGER NOT NULL,
  member            INTEGER NOT NULL,
  genes             BLOB NOT NULL,
  genes_json        TEXT NOT NULL,
  valid             INTEGER NOT NULL,
  fitness           REAL,
  reason            TEXT NOT NULL DEFAULT '',
  worker_id         TEXT NOT NULL DEFAULT '',
  eval_seconds      REAL NOT NULL DEFAULT 0,
  carried           INTEGER NOT NULL DEFAULT 0,
  origin_generation INTEGER NOT NULL,
  origin_member     INTEGER NOT NULL,
  reported_ms       INTEGER NOT NULL,
  PRIMARY KEY (study_id, generation, member)
) WITHOUT ROWID;

CREATE TABLE metrics (
  study_id   TEXT NOT NULL,
  generation INTEGER NOT NULL,
  member     INTEGER NOT NULL,
  name       TEXT NOT NULL,
  value      REAL,
  PRIMARY KEY (study_id, generation, member, name)
) WITHOUT ROWID;

-- The hall of fame after each generation, best first (rank 0).
CREATE TABLE hall_of_fame (
  study_id          TEXT NOT NULL REFERENCES studies(study_id),
  generation        INTEGER NOT NULL,
  rank              INTEGER NOT NULL,
  origin_generation INTEGER NOT NULL,
  origin_member     INTEGER NOT NULL,
  genes             BLOB NOT NULL,
  genes_json        TEXT NOT NULL,
  valid             INTEGER NOT NULL,
  fitness           REAL,
  PRIMARY KEY (study_id, generation, rank)
) WITHOUT ROWID;

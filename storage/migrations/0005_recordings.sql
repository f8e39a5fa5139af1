-- Schema version 5: recordings, content-addressed (docs/recording-format.md).
CREATE TABLE recordings (
  hash         TEXT PRIMARY KEY,      -- lowercase hex SHA-256 of csv || 0x00 || sidecar
  name         TEXT NOT NULL,         -- file name it was added from
  robot        TEXT NOT NULL,
  rows         INTEGER NOT NULL,
  channels     TEXT NOT NULL,         -- comma-separated channel names
  dt           REAL NOT NULL,         -- nominal sampling interval, s
  dropped_rows INTEGER NOT NULL,
  csv          BLOB NOT NULL,
  sidecar      BLOB NOT NULL,
  added_ms     INTEGER NOT NULL
) WITHOUT ROWID;

-- Schema version 2: what the job queue saw while each generation ran (issue 5's checker
-- and people debugging a cluster read these). Counts of the coordinator process that
-- committed the generation; a coordinator restart mid-generation starts them from 0.
ALTER TABLE generations ADD COLUMN leases INTEGER NOT NULL DEFAULT 0;
ALTER TABLE generations ADD COLUMN lease_expiries INTEGER NOT NULL DEFAULT 0;
ALTER TABLE generations ADD COLUMN duplicates INTEGER NOT NULL DEFAULT 0;
ALTER TABLE generations ADD COLUMN backups INTEGER NOT NULL DEFAULT 0;
ALTER TABLE generations ADD COLUMN poisoned INTEGER NOT NULL DEFAULT 0;

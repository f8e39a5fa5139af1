-- Schema version 4: each member's total constraint violation (0 = feasible), so that
-- feasibility is visible in the database (docs/spec.md, "constraints").
ALTER TABLE individuals ADD COLUMN violation REAL NOT NULL DEFAULT 0;

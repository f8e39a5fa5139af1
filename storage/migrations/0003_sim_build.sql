-- Schema version 3: the simulator build a study's results come from. Pinned by the first
-- lease; workers of another build are refused for that study (docs/protocol.md).
ALTER TABLE studies ADD COLUMN sim_build TEXT NOT NULL DEFAULT '';

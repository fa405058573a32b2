-- The counters of automatic operation a controller keeps through a restart (FANUC keeps its
-- operating time No.6751/6752 and cutting time No.6753/6754 through power off), in simulated
-- seconds; 0 for the controllers stored before them.
ALTER TABLE controllers ADD COLUMN operating_time_s REAL NOT NULL DEFAULT 0;
ALTER TABLE controllers ADD COLUMN cutting_time_s REAL NOT NULL DEFAULT 0;

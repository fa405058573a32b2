-- The counters of automatic operation (`../0008_operation_times.sql`).
ALTER TABLE controllers ADD COLUMN operating_time_s DOUBLE PRECISION NOT NULL DEFAULT 0;
ALTER TABLE controllers ADD COLUMN cutting_time_s DOUBLE PRECISION NOT NULL DEFAULT 0;

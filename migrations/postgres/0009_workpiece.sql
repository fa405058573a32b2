-- What is clamped on a controller's table (`../0009_workpiece.sql`).
ALTER TABLE controllers ADD COLUMN workpiece TEXT;

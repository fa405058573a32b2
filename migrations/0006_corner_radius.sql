-- The tool's corner radius per tool offset number (FANUC's corner-R offset data), which cutting
-- point control (G43.8/G43.9) reads; 0 (a square end mill, or a ball end mill read from D) for
-- the offsets stored before it.
ALTER TABLE tool_offsets ADD COLUMN corner_radius REAL NOT NULL DEFAULT 0;

-- The tool's corner radius per tool offset number (`../0006_corner_radius.sql`).
ALTER TABLE tool_offsets ADD COLUMN corner_radius DOUBLE PRECISION NOT NULL DEFAULT 0;

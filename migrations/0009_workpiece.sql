-- What is clamped on a controller's table, the boxes a G31 probe touches: the engine's JSON
-- {"boxes": [{"min": [x, y, z], "max": [x, y, z]}, …]} (`engine/src/workpiece.rs`, table frame,
-- mm); NULL for the controllers stored before it, which is nothing on the table, as
-- {"boxes": []} is.
ALTER TABLE controllers ADD COLUMN workpiece TEXT;

-- The tilted working plane a controller keeps over a restart (`../0005_kept_plane.sql`).
ALTER TABLE controllers ADD COLUMN kept_plane TEXT;

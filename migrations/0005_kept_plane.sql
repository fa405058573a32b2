-- The tilted working plane a controller keeps over a restart (Syntec Pr3014 = 2): a JSON
-- object {"code", "origin", "axes"} (engine `interp::KeptPlane`), NULL when none is kept.
ALTER TABLE controllers ADD COLUMN kept_plane TEXT;

-- Vendor parameters the machine model does not read (`../0003_extra_parameters.sql`).
ALTER TABLE controllers ADD COLUMN extra_parameters TEXT NOT NULL DEFAULT '{}';

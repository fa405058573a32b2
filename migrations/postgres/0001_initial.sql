-- fivex initial schema, PostgreSQL (the same tables as `../0001_initial.sql` for SQLite: BIGINT
-- for SQLite's INTEGER, DOUBLE PRECISION for its REAL, an identity for AUTOINCREMENT).
CREATE TABLE controllers (
    id           TEXT PRIMARY KEY,
    name         TEXT NOT NULL,
    dialect      TEXT NOT NULL,
    machine_json TEXT NOT NULL,
    created_at   TEXT NOT NULL
);

CREATE TABLE programs (
    controller_id TEXT   NOT NULL REFERENCES controllers(id) ON DELETE CASCADE,
    number        BIGINT NOT NULL,
    text          TEXT   NOT NULL,
    PRIMARY KEY (controller_id, number)
);

CREATE TABLE variables (
    controller_id TEXT   NOT NULL REFERENCES controllers(id) ON DELETE CASCADE,
    number        BIGINT NOT NULL,
    value         DOUBLE PRECISION,
    PRIMARY KEY (controller_id, number)
);

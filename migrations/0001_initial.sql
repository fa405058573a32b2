-- fivex initial schema.
--
-- One row per virtual controller; its machine configuration is stored as the JSON document the
-- API accepted (the same format as a `--machine FILE.json`). Times are RFC 3339 UTC text.
CREATE TABLE controllers (
    id           TEXT PRIMARY KEY,
    name         TEXT NOT NULL,
    dialect      TEXT NOT NULL,
    machine_json TEXT NOT NULL,
    created_at   TEXT NOT NULL
);

-- Stored NC programs (O-numbers), one per controller and number; `text` is the NC source.
CREATE TABLE programs (
    controller_id TEXT    NOT NULL REFERENCES controllers(id) ON DELETE CASCADE,
    number        INTEGER NOT NULL,
    text          TEXT    NOT NULL,
    PRIMARY KEY (controller_id, number)
);

-- Persistent (retained) custom macro variables #500-#999. A NULL value is a vacant variable
-- (#0 semantics); a missing row is vacant too.
CREATE TABLE variables (
    controller_id TEXT    NOT NULL REFERENCES controllers(id) ON DELETE CASCADE,
    number        INTEGER NOT NULL,
    value         REAL,
    PRIMARY KEY (controller_id, number)
);

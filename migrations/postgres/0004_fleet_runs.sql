-- Fleet runs (`../0004_fleet_runs.sql`). `rowid` is SQLite's implicit insertion order, which
-- the queries order by.
CREATE TABLE fleet_runs (
    id TEXT PRIMARY KEY,
    created_at TEXT NOT NULL,
    finished_at TEXT,
    status TEXT NOT NULL,
    machines BIGINT NOT NULL,
    completed BIGINT NOT NULL DEFAULT 0,
    alarms BIGINT NOT NULL DEFAULT 0,
    program TEXT NOT NULL,
    request_json TEXT NOT NULL,
    results_json TEXT,
    rowid BIGINT GENERATED ALWAYS AS IDENTITY UNIQUE
);

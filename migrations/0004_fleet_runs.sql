-- Fleet runs (POST /api/v1/fleet/runs, docs/fleet.md): the request as given and, once the run
-- is done, the fleet array (one run summary per machine). A run the service was stopped in the
-- middle of is marked 'interrupted' on the next start.
CREATE TABLE fleet_runs (
    id TEXT PRIMARY KEY,
    created_at TEXT NOT NULL,
    finished_at TEXT,
    status TEXT NOT NULL,
    machines INTEGER NOT NULL,
    completed INTEGER NOT NULL DEFAULT 0,
    alarms INTEGER NOT NULL DEFAULT 0,
    program TEXT NOT NULL,
    request_json TEXT NOT NULL,
    results_json TEXT
);

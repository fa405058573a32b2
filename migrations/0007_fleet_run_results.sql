-- Each machine's result of a fleet run over NATS, recorded as it arrives (docs/fleet.md, "Over
-- NATS"): any node reads a run's progress, and a node that takes over a run whose collecting
-- node died records only what is missing (the key: a machine's result is never recorded twice).
-- Deleted when the run is stored as over (its results are then in fleet_runs.results_json).
CREATE TABLE fleet_run_results (
    run_id TEXT NOT NULL,
    idx INTEGER NOT NULL,
    result_json TEXT NOT NULL,
    PRIMARY KEY (run_id, idx)
);
-- The nodes of a cluster look for the runs under way at every beat.
CREATE INDEX fleet_runs_status ON fleet_runs (status);

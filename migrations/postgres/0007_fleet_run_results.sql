-- Each machine's result of a fleet run over NATS as it arrives (`../0007_fleet_run_results.sql`).
CREATE TABLE fleet_run_results (
    run_id TEXT NOT NULL,
    idx BIGINT NOT NULL,
    result_json TEXT NOT NULL,
    PRIMARY KEY (run_id, idx)
);
CREATE INDEX fleet_runs_status ON fleet_runs (status);

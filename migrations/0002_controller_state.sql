-- What a controller keeps besides its programs and retained variables (issue 6).
--
-- The speed factor of simulated time (1 = real time).
ALTER TABLE controllers ADD COLUMN speed REAL NOT NULL DEFAULT 1.0;

-- Tool offset memory C: geometry and wear of H (length) and D (radius) per offset number.
CREATE TABLE tool_offsets (
    controller_id TEXT    NOT NULL REFERENCES controllers(id) ON DELETE CASCADE,
    number        INTEGER NOT NULL,
    length        REAL    NOT NULL DEFAULT 0,
    length_wear   REAL    NOT NULL DEFAULT 0,
    radius        REAL    NOT NULL DEFAULT 0,
    radius_wear   REAL    NOT NULL DEFAULT 0,
    PRIMARY KEY (controller_id, number)
);

-- Work offsets: `slot` 0 is the external offset, 1-6 G54-G59, 7.. G54.1 P1...; `axes` a JSON
-- array of the offset per machine axis.
CREATE TABLE work_offsets (
    controller_id TEXT    NOT NULL REFERENCES controllers(id) ON DELETE CASCADE,
    slot          INTEGER NOT NULL,
    axes          TEXT    NOT NULL,
    PRIMARY KEY (controller_id, slot)
);

-- Every alarm a controller raised, oldest first.
CREATE TABLE alarm_history (
    id            INTEGER PRIMARY KEY AUTOINCREMENT,
    controller_id TEXT    NOT NULL REFERENCES controllers(id) ON DELETE CASCADE,
    raised_at     TEXT    NOT NULL,
    code          TEXT    NOT NULL,
    message       TEXT    NOT NULL,
    line          INTEGER NOT NULL,
    n             INTEGER
);
CREATE INDEX alarm_history_by_controller ON alarm_history (controller_id, id);

-- Every program run: which program, wall-clock start and end, simulated cycle time, and how it
-- ended (`completed`, `alarm`, `reset`).
CREATE TABLE run_history (
    id            INTEGER PRIMARY KEY AUTOINCREMENT,
    controller_id TEXT    NOT NULL REFERENCES controllers(id) ON DELETE CASCADE,
    program       INTEGER,
    started_at    TEXT    NOT NULL,
    ended_at      TEXT    NOT NULL,
    cycle_time_s  REAL    NOT NULL,
    result        TEXT    NOT NULL
);
CREATE INDEX run_history_by_controller ON run_history (controller_id, id);

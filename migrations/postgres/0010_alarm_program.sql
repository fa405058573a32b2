-- The program an alarm's line is in (`../0010_alarm_program.sql`).
ALTER TABLE alarm_history ADD COLUMN program BIGINT;

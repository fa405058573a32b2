-- The O number of the stored program an alarm's line is in (the selected program or one it
-- called); NULL for MDI's own blocks and the alarms recorded before it was kept.
ALTER TABLE alarm_history ADD COLUMN program INTEGER;

-- A dataset's listing header (curve index and summary rows, lab units) stored beside the
-- dataset, so that GET /datasets reads small columns instead of parsing every stored
-- dataset under the database lock. Rows stored before this column are filled in at
-- start-up (Service::backfill_dataset_headers).
ALTER TABLE datasets ADD COLUMN header_json TEXT;

-- A diagnosis started again from an interrupted (or finished) one names its origin, as
-- runs.rerun_of does.
ALTER TABLE diagnoses ADD COLUMN rerun_of INTEGER REFERENCES diagnoses(id) ON DELETE SET NULL;

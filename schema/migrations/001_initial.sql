-- Initial store of triaxd. Lab units are not stored here: scheme, result and dataset
-- documents are JSON in the same units as the REST API (unit in every field name).
CREATE TABLE schemes (
  id          INTEGER PRIMARY KEY,
  name        TEXT NOT NULL,
  scheme_json TEXT NOT NULL,
  created_at  TEXT NOT NULL
);

CREATE TABLE runs (
  id           INTEGER PRIMARY KEY,
  scheme_id    INTEGER NOT NULL REFERENCES schemes(id),
  name         TEXT NOT NULL,
  status       TEXT NOT NULL CHECK (status IN ('queued','running','done','failed','cancelled','interrupted')),
  stage        TEXT,
  progress_pct REAL NOT NULL DEFAULT 0,
  eta_s        REAL,
  threads      INTEGER NOT NULL DEFAULT 1,
  rerun_of     INTEGER REFERENCES runs(id),
  created_at   TEXT NOT NULL,
  started_at   TEXT,
  finished_at  TEXT,
  error        TEXT
);
CREATE INDEX runs_by_status ON runs(status);

-- Every event a run streamed, in order: the SSE replay source and the partial series.
CREATE TABLE run_events (
  run_id INTEGER NOT NULL REFERENCES runs(id) ON DELETE CASCADE,
  seq    INTEGER NOT NULL,
  type   TEXT NOT NULL,
  data   TEXT NOT NULL,
  PRIMARY KEY (run_id, seq)
) WITHOUT ROWID;

-- The engine's final result in lab units (summary and complete series), written once.
CREATE TABLE run_results (
  run_id      INTEGER PRIMARY KEY REFERENCES runs(id) ON DELETE CASCADE,
  result_json TEXT NOT NULL
);

CREATE TABLE datasets (
  id           INTEGER PRIMARY KEY,
  name         TEXT NOT NULL,
  format       TEXT NOT NULL,
  dataset_json TEXT NOT NULL,
  created_at   TEXT NOT NULL
);

CREATE TABLE comparisons (
  id          INTEGER PRIMARY KEY,
  run_id      INTEGER NOT NULL REFERENCES runs(id) ON DELETE CASCADE,
  dataset_id  INTEGER NOT NULL REFERENCES datasets(id) ON DELETE CASCADE,
  result_json TEXT NOT NULL,
  created_at  TEXT NOT NULL
);

CREATE TABLE diagnoses (
  id           INTEGER PRIMARY KEY,
  dataset_id   INTEGER NOT NULL REFERENCES datasets(id) ON DELETE CASCADE,
  status       TEXT NOT NULL CHECK (status IN ('queued','running','done','failed','cancelled','interrupted')),
  progress_pct REAL NOT NULL DEFAULT 0,
  request_json TEXT NOT NULL,
  report_json  TEXT,
  error        TEXT,
  created_at   TEXT NOT NULL,
  finished_at  TEXT
);

CREATE TABLE diagnosis_events (
  diagnosis_id INTEGER NOT NULL REFERENCES diagnoses(id) ON DELETE CASCADE,
  seq          INTEGER NOT NULL,
  type         TEXT NOT NULL,
  data         TEXT NOT NULL,
  PRIMARY KEY (diagnosis_id, seq)
) WITHOUT ROWID;

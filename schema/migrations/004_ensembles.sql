-- Ensembles (POST /ensembles): one scheme run at several seeds as one job. `seeds` is the
-- list as the client gave it ("1-8"); members_total its size. Status follows runs: a job
-- left queued or running by a killed process reads back as 'interrupted' at start-up.
CREATE TABLE ensembles (
  id            INTEGER PRIMARY KEY,
  scheme_id     INTEGER NOT NULL REFERENCES schemes(id),
  name          TEXT NOT NULL,
  seeds         TEXT NOT NULL,
  status        TEXT NOT NULL CHECK (status IN ('queued','running','done','failed','cancelled','interrupted')),
  members_total INTEGER NOT NULL,
  members_done  INTEGER NOT NULL DEFAULT 0,
  concurrency   INTEGER NOT NULL DEFAULT 1,
  created_at    TEXT NOT NULL,
  started_at    TEXT,
  finished_at   TEXT,
  error         TEXT
);
CREATE INDEX ensembles_by_status ON ensembles(status);

-- The finished ensemble, written once with its 'done': the summary with its bands (lab
-- units, scaleout::ensemble_to_json) and the two band tables as served.
CREATE TABLE ensemble_results (
  ensemble_id    INTEGER PRIMARY KEY REFERENCES ensembles(id) ON DELETE CASCADE,
  summary_json   TEXT NOT NULL,
  shear_band_csv TEXT NOT NULL,
  creep_band_csv TEXT NOT NULL
);

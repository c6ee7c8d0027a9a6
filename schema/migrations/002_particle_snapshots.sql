-- The specimen at the end of each stage of a run (docs/packings.md): the engine's
-- SpecimenSnapshot in its compact stored form (server/io/packing_codec.cpp: binary, exact
-- doubles, zlib), with the counts the list shows without decoding it.
CREATE TABLE run_snapshots (
  run_id             INTEGER NOT NULL REFERENCES runs(id) ON DELETE CASCADE,
  stage              TEXT NOT NULL,
  seq                INTEGER NOT NULL,
  grains             INTEGER NOT NULL,
  membrane_particles INTEGER NOT NULL,
  contacts           INTEGER NOT NULL,
  data               BLOB NOT NULL,
  PRIMARY KEY (run_id, stage)
) WITHOUT ROWID;

-- Packings uploaded to start runs from (grains only, as the project JSON in SI units).
CREATE TABLE packings (
  id           INTEGER PRIMARY KEY,
  name         TEXT NOT NULL,
  format       TEXT NOT NULL,
  grains       INTEGER NOT NULL,
  packing_json TEXT NOT NULL,
  created_at   TEXT NOT NULL
);

-- The packing a run starts from (NULL: the specimen is generated).
ALTER TABLE runs ADD COLUMN packing_id INTEGER REFERENCES packings(id);

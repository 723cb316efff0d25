//! Per-muscle displacement fields, precomputed once per rig and mesh.

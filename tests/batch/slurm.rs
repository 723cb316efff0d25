//! A real single-node Slurm cluster (see examples/slurm/cluster-test.sh).

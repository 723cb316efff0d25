//! The classic Waters data files.

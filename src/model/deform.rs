//! The deformation: a sparse blend of muscle fields, then the jaw.

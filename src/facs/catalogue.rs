//! The FACS Action Unit catalogue: numbers, names and muscular basis.

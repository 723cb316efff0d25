//! The built-in default face: a procedural neutral adult face mesh and its rigs.

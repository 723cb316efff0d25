//! Combination strings as FACS writes them: `1+2+5B+26`, `R12A+R14A`, `6+12@0.5`.

//! The terminal editor (ratatui + crossterm).

//! FACS: Action Unit keys and catalogue, AU tables and combination strings.

pub mod au;
pub mod catalogue;
pub mod combo;
pub mod table;

pub use au::{AuKey, AuKeyError};
pub use table::{AuEntry, AuTable, MAX_AUS, TABLE_VERSION};

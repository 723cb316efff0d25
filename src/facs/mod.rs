//! FACS: Action Unit keys and catalogue, AU tables, combination strings and the mapper from
//! AUs to activations.

pub mod au;
pub mod catalogue;
pub mod combo;
pub mod mapper;
pub mod table;

pub use au::{AuKey, AuKeyError};
pub use mapper::{clamp_to_ranges, AuMapper};
pub use table::{AuEntry, AuTable, MAX_AUS, TABLE_VERSION};

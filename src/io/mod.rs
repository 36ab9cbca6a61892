//! Reading and writing measurement files.

pub mod csv_table;

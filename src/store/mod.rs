//! SQLite storage: schema, migrations, the append-only review log.
//! Never imports ratatui.

pub mod cli;

//! Scheduling: FSRS-6 with learning steps. Never imports ratatui.

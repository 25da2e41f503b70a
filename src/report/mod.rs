//! Turns run results into the published Markdown reports.

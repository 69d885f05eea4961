//! WIF 1.1 weave drafts (being written).

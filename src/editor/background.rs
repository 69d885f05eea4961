//! (being written for issue 48)

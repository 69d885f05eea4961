//! `clothbake fit` and the library's fit (src/fit/): sample files as untrusted input, the
//! round trip from a moved fabric's noisy samples back to its F, thread-count independence,
//! and the command end to end.

mod cli;
mod round_trip;
mod samples;

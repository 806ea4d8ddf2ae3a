//! Reader tests: structure.

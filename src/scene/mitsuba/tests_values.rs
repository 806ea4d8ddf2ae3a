//! Reader tests: values.

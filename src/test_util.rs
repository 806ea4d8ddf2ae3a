//! Helpers shared by the unit tests of several modules.

use std::fmt::{Debug, Display};

/// Asserts that `parse` rejects each input of `cases` with an error message that contains the
/// text paired with it.
pub(crate) fn assert_rejects<T: Debug, E: Display>(
    parse: impl Fn(&str) -> Result<T, E>,
    cases: &[(&str, &str)],
) {
    for (input, says) in cases {
        match parse(input) {
            Ok(v) => panic!("{input:?} was accepted as {v:?}"),
            Err(e) => assert!(e.to_string().contains(says), "{input:?}: {e}"),
        }
    }
}

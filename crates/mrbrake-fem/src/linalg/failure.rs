//! faer's failures in words: its error types print as `Debug` (`SymbolicSingular { index: 2531
//! }`), which names nothing a user can act on (issue 33, class 4). These say what happened and
//! what commonly causes it.

use faer::sparse::FaerError;
use faer::sparse::linalg::LuError;

/// A failure of faer's sparse machinery (allocation or index range), in words.
pub(crate) fn faer_words(e: &FaerError) -> &'static str {
    match e {
        FaerError::IndexOverflow => {
            "the system is too large for the sparse matrix's index type (index overflow)"
        }
        FaerError::OutOfMemory => {
            "memory allocation failed: the system is too large for the memory available (a coarser \
             mesh or a lower element order needs less)"
        }
        _ => "the sparse linear algebra failed",
    }
}

/// A failure of the sparse LU factorisation, in words.
pub(crate) fn lu_words(e: &LuError) -> String {
    match e {
        LuError::SymbolicSingular { index } => format!(
            "the matrix is structurally singular (no pivot at elimination step {index}): some \
             unknowns have no equation, e.g. a region with no material or cut off from every \
             boundary condition"
        ),
        LuError::Generic(e) => faer_words(e).to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failures_read_as_words_without_debug_braces() {
        for text in [
            lu_words(&LuError::SymbolicSingular { index: 2531 }),
            lu_words(&LuError::Generic(FaerError::OutOfMemory)),
            faer_words(&FaerError::IndexOverflow).to_string(),
        ] {
            assert!(!text.contains('{') && !text.contains("Generic"), "{text}");
            assert!(text.len() > 30, "{text}");
        }
        assert!(lu_words(&LuError::SymbolicSingular { index: 7 }).contains("step 7"));
    }
}

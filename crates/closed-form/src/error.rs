//! Errors of the closed-form crate.

use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum ClosedFormError {
    #[error("invalid parameters: {0}")]
    Parameters(String),
    #[error("(m, h) is outside the admissible region: {0}")]
    NotAdmissible(String),
    #[error("(m, h) lies on the bifurcation diagram Σ: {0}; the integral manifold is critical there (a separated variable sits at a multiple root), pick a point off Σ")]
    OnSigma(String),
    #[error("torus {torus} does not exist: camera {camera} has {}", tori_phrase(*.tori))]
    NoSuchTorus {
        torus: usize,
        camera: String,
        tori: usize,
    },
    /// A parameter outside the documented range of the closed form (docs/closed-form.md):
    /// the parameter's name (`a`, `b`, `m`, `h`) and why.
    #[error("{1}")]
    Range(&'static str, String),
    #[error("internal error: {0}")]
    Internal(String),
}

/// How many tori a camera has and which indices are valid: "1 torus (only torus 0)", "2 tori
/// (0 and 1)", "4 tori (0 to 3)".
pub fn tori_phrase(tori: usize) -> String {
    match tori {
        0 => "no torus".into(),
        1 => "1 torus (only torus 0)".into(),
        2 => "2 tori (0 and 1)".into(),
        n => format!("{n} tori (0 to {})", n - 1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The valid range is said right (old text: "has 1 torus/tori (0..1)", read as 0 and 1).
    #[test]
    fn the_torus_message_gives_the_valid_range() {
        let e = |torus, tori| {
            ClosedFormError::NoSuchTorus {
                torus,
                camera: "I+".into(),
                tori,
            }
            .to_string()
        };
        assert_eq!(
            e(1, 1),
            "torus 1 does not exist: camera I+ has 1 torus (only torus 0)"
        );
        assert_eq!(
            e(2, 2),
            "torus 2 does not exist: camera I+ has 2 tori (0 and 1)"
        );
        assert_eq!(
            e(4, 4),
            "torus 4 does not exist: camera I+ has 4 tori (0 to 3)"
        );
    }
}

//! Enums a user names by a word (`--method watertight`, `effects: ["facing-ratio"]`, `--bug negative-t`):
//! one parser and one message for all of them. Each enum derives its list of values
//! (`strum::EnumIter`) and its kebab-case words (`strum::IntoStaticStr`); nothing here is written per enum.

use strum::IntoEnumIterator;

/// A word that names none of an enum's values; its message lists every word that would.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown {what} '{word}' (expected one of {})", .expected.join(", "))]
pub struct UnknownName {
    /// What was being named ("method", "bug", …).
    pub what: &'static str,
    /// The word as given.
    pub word: String,
    /// Every word that names a value, in the enum's order.
    pub expected: Vec<&'static str>,
}

/// The value named `word`, or [`UnknownName`] listing every word.
pub fn parse<T>(what: &'static str, word: &str) -> Result<T, UnknownName>
where
    T: IntoEnumIterator + Into<&'static str> + Copy,
{
    T::iter()
        .find(|value| Into::<&'static str>::into(*value) == word)
        .ok_or_else(|| UnknownName {
            what,
            word: word.to_string(),
            expected: T::iter().map(Into::into).collect(),
        })
}

#[cfg(test)]
mod tests {
    /// An enum named by words as raylab's are (the real ones live in higher layers, which this module
    /// may not import, tests included).
    #[derive(Clone, Copy, Debug, PartialEq, strum::EnumIter, strum::IntoStaticStr)]
    #[strum(serialize_all = "kebab-case")]
    enum Method {
        Cramer,
        MollerTrumbore,
        WatertightExact,
        Exact,
    }

    #[test]
    fn a_word_names_its_value_and_a_typo_lists_every_word() {
        assert_eq!(
            super::parse::<Method>("method", "moller-trumbore"),
            Ok(Method::MollerTrumbore)
        );
        let error = super::parse::<Method>("method", "moller")
            .unwrap_err()
            .to_string();
        assert_eq!(
            error,
            "unknown method 'moller' (expected one of cramer, moller-trumbore, watertight-exact, exact)"
        );
    }
}

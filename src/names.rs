//! Enums a user names by a word (`--method watertight`, `effects: ["facing-ratio"]`, `--bug negative-t`):
//! one parser and one message for all of them. Each enum derives its list of values
//! (`strum::EnumIter`) and its kebab-case words (`strum::IntoStaticStr`); nothing here is written per enum.

use strum::IntoEnumIterator;

/// The value named `word`, or `unknown {what} '{word}' (expected one of …)` listing every word.
pub fn parse<T>(what: &str, word: &str) -> Result<T, String>
where
    T: IntoEnumIterator + Into<&'static str> + Copy,
{
    T::iter()
        .find(|value| Into::<&'static str>::into(*value) == word)
        .ok_or_else(|| {
            let words: Vec<&'static str> = T::iter().map(Into::into).collect();
            format!(
                "unknown {what} '{word}' (expected one of {})",
                words.join(", ")
            )
        })
}

#[cfg(test)]
mod tests {
    use crate::intersect::Method;

    #[test]
    fn a_word_names_its_value_and_a_typo_lists_every_word() {
        assert_eq!(
            super::parse::<Method>("method", "moller-trumbore"),
            Ok(Method::MollerTrumbore)
        );
        let error = super::parse::<Method>("method", "moller").unwrap_err();
        assert!(
            error.starts_with("unknown method 'moller' (expected one of cramer, moller-trumbore")
        );
        assert!(
            error.ends_with("watertight, watertight-exact, exact)"),
            "{error}"
        );
    }
}

//! Where a line of math may wrap. egui wraps at any space; in "17. Check β ≥ 0" that leaves "≥ 0" alone
//! on the next row. These put non-breaking spaces where a break would split a formula.

/// U+00A0, which egui does not break at.
const KEEP: char = '\u{a0}';

/// Binary operators and relations: a formula goes on across them.
const OPERATORS: [&str; 13] = [
    "=", "≠", "≤", "≥", "<", ">", "+", "−", "-", "·", "×", "/", "∈",
];

/// A word of math: an operator, a single symbol (`β`, `M`, `0`), or one with digits, brackets,
/// bars or marks no English word has (`M1:`, `(α,`, `t)ᵀ`, `|M|`, `M⁻¹`).
fn is_math(word: &str) -> bool {
    let word = word.trim_end_matches([',', ':', ';', '.']);
    OPERATORS.contains(&word)
        || word.chars().count() == 1
        || word.chars().any(|c| {
            c.is_ascii_digit() || "()|[]·×−=≤≥⁻¹ᵀ²³_".contains(c) || ('₀'..='₉').contains(&c)
        })
}

/// Prose with its formulas kept whole: the spaces between two words of math, or beside an operator,
/// do not break ("17. Check β ≥ 0" wraps after "Check" if at all).
pub fn keep_formulas_whole(text: &str) -> String {
    let words: Vec<&str> = text.split(' ').collect();
    let mut out = String::with_capacity(text.len() + 8);
    for (i, word) in words.iter().enumerate() {
        if i > 0 {
            let before = words[i - 1];
            let glued = OPERATORS.contains(&before)
                || OPERATORS.contains(word)
                || (is_math(before) && is_math(word));
            out.push(if glued { KEEP } else { ' ' });
        }
        out.push_str(word);
    }
    out
}

/// A formula line that wraps only before a top-level `=`, `≈`, `+` or `−` (outside brackets), the way
/// a long equation is broken by hand: "3·0 − 3·(−3)" breaks before "−", never inside a term.
pub fn break_between_terms(text: &str) -> String {
    let mut depth = 0i32;
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len() + 8);
    for (i, &c) in chars.iter().enumerate() {
        match c {
            '(' | '[' => depth += 1,
            ')' | ']' => depth -= 1,
            _ => {}
        }
        if c == ' ' {
            let next = chars.get(i + 1).copied();
            let after = chars.get(i + 2).copied();
            let breaks = depth <= 0
                && matches!(next, Some('=' | '≈' | '+' | '−' | '-'))
                && after.is_none_or(|a| a == ' ');
            out.push(if breaks { ' ' } else { KEEP });
        } else {
            out.push(c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shown(text: &str) -> String {
        text.replace(KEEP, "_")
    }

    #[test]
    fn a_title_keeps_its_formula_whole() {
        assert_eq!(
            shown(&keep_formulas_whole("17. Check β ≥ 0")),
            "17. Check β_≥_0"
        );
        assert_eq!(
            shown(&keep_formulas_whole("The system M X = Y")),
            "The system M_X_=_Y"
        );
        assert_eq!(
            shown(&keep_formulas_whole("M1: M with column 1 replaced by Y")),
            "M1:_M with column 1 replaced by Y"
        );
        assert_eq!(
            shown(&keep_formulas_whole("Hit point o + t d")),
            "Hit point o_+_t_d"
        );
    }

    #[test]
    fn a_formula_breaks_only_between_terms() {
        assert_eq!(
            shown(&break_between_terms("t = 3·0 − 3·(−3 + 1)")),
            "t =_3·0 −_3·(−3_+_1)"
        );
        assert_eq!(
            shown(&break_between_terms("|M| = 27 / 27")),
            "|M| =_27_/_27"
        );
    }
}

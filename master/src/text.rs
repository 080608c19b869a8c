//! The closest valid name to a misspelled one, for messages ("did you mean …?").

/// The name of `names` closest to `name` by normalised Damerau–Levenshtein similarity, when
/// it is at least 0.5 (nothing is suggested for a name unlike every valid one).
pub fn closest<'a>(name: &str, names: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    names
        .into_iter()
        .map(|n| (strsim::normalized_damerau_levenshtein(name, n), n))
        .filter(|(score, _)| *score >= 0.5)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, n)| n)
}

/// `; did you mean "x"?` for the [`closest`] of `names` to `name`, or nothing: the tail of
/// a message naming an unknown component or variable.
pub fn did_you_mean<'a>(name: &str, names: impl IntoIterator<Item = &'a str>) -> String {
    closest(name, names)
        .map(|n| format!("; did you mean \"{n}\"?"))
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::closest;

    #[test]
    fn the_close_name_or_none() {
        let names = ["speed_kmh", "dt_s", "solver"];
        assert_eq!(closest("sped_kmh", names), Some("speed_kmh"));
        assert_eq!(closest("solvr", names), Some("solver"));
        assert_eq!(closest("xyzzy", names), None);
    }
}

//! Units as the model writes them (`"m"`, `"rad/s"`, `"N m"`, `"kg m²"`, `"m/s²"`) and as
//! FMI defines them: a `<Unit>` with the exponents of the SI base units (`<BaseUnit kg="1"
//! m="2"/>`), so that an importer can check and convert what it connects. A unit this reader
//! does not know is still declared, by name, without a `BaseUnit`.

/// The exponents of kg, m, s, A, K, mol, cd and rad, in that order (FMI's `BaseUnit`
/// attributes).
pub type Exponents = [i32; 8];

/// The attribute names of [`Exponents`].
pub const BASE: [&str; 8] = ["kg", "m", "s", "A", "K", "mol", "cd", "rad"];

/// The base exponents of a unit symbol.
fn symbol(name: &str) -> Option<Exponents> {
    Some(match name {
        "1" => [0, 0, 0, 0, 0, 0, 0, 0],
        "kg" => [1, 0, 0, 0, 0, 0, 0, 0],
        "m" => [0, 1, 0, 0, 0, 0, 0, 0],
        "s" => [0, 0, 1, 0, 0, 0, 0, 0],
        "A" => [0, 0, 0, 1, 0, 0, 0, 0],
        "K" => [0, 0, 0, 0, 1, 0, 0, 0],
        "mol" => [0, 0, 0, 0, 0, 1, 0, 0],
        "cd" => [0, 0, 0, 0, 0, 0, 1, 0],
        "rad" => [0, 0, 0, 0, 0, 0, 0, 1],
        "Hz" => [0, 0, -1, 0, 0, 0, 0, 0],
        "N" => [1, 1, -2, 0, 0, 0, 0, 0],
        "J" => [1, 2, -2, 0, 0, 0, 0, 0],
        "W" => [1, 2, -3, 0, 0, 0, 0, 0],
        "Pa" => [1, -1, -2, 0, 0, 0, 0, 0],
        _ => return None,
    })
}

/// A factor with its exponent: `m²`, `s^-2`, `kg`.
fn factor(text: &str) -> Option<(Exponents, i32)> {
    let superscripts = [('¹', 1), ('²', 2), ('³', 3), ('⁴', 4)];
    for (mark, power) in superscripts {
        if let Some(base) = text.strip_suffix(mark) {
            return Some((symbol(base)?, power));
        }
    }
    if let Some((base, power)) = text.split_once('^') {
        return Some((symbol(base)?, power.parse().ok()?));
    }
    // `m2`, `s-2`: a symbol followed by an integer exponent.
    let split = text
        .find(|c: char| c.is_ascii_digit() || c == '-')
        .filter(|&i| i > 0);
    if let Some(i) = split {
        return Some((symbol(&text[..i])?, text[i..].parse().ok()?));
    }
    Some((symbol(text)?, 1))
}

/// The base exponents of a unit: factors separated by spaces, `*` or `·`, each `/` dividing
/// by the factor after it (`N m`, `kg m²`, `m/s²`, `rad/s/s`). `None` for a unit with a
/// symbol this reader does not know.
pub fn exponents(unit: &str) -> Option<Exponents> {
    let mut total = [0; 8];
    let mut sign = 1;
    let mut any = false;
    let spaced = unit.replace('/', " / ").replace(['*', '·'], " ");
    for token in spaced.split_whitespace() {
        if token == "/" {
            sign = -1;
            continue;
        }
        let (base, power) = factor(token)?;
        for (t, b) in total.iter_mut().zip(base) {
            *t += sign * power * b;
        }
        sign = 1;
        any = true;
    }
    any.then_some(total)
}

/// The unit of a quantity's time derivative: `m` gives `m/s`, `rad/s` gives `rad/s²`, with
/// the time's unit `time` (`None` when either is unknown).
pub fn per_time(unit: Option<&str>, time: Option<&str>) -> Option<String> {
    let (unit, time) = (unit?, time?);
    if time == "s" {
        if let Some(base) = unit.strip_suffix("/s") {
            return Some(format!("{base}/s²"));
        }
    }
    Some(format!("{unit}/{time}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_catalogue_s_units() {
        assert_eq!(exponents("m"), Some([0, 1, 0, 0, 0, 0, 0, 0]));
        assert_eq!(exponents("rad/s"), Some([0, 0, -1, 0, 0, 0, 0, 1]));
        assert_eq!(exponents("N m"), Some([1, 2, -2, 0, 0, 0, 0, 0]));
        assert_eq!(exponents("N m"), exponents("J"));
        assert_eq!(exponents("kg m²"), Some([1, 2, 0, 0, 0, 0, 0, 0]));
        assert_eq!(exponents("m/s²"), Some([0, 1, -2, 0, 0, 0, 0, 0]));
        assert_eq!(exponents("rad/s²"), exponents("rad/s/s"));
        assert_eq!(exponents("kg*m^2"), exponents("kg m²"));
        assert_eq!(exponents("m s-2"), exponents("m/s²"));
        assert_eq!(exponents("furlong"), None);
        assert_eq!(exponents(""), None);
    }

    #[test]
    fn derivatives_divide_by_the_time() {
        assert_eq!(per_time(Some("m"), Some("s")).as_deref(), Some("m/s"));
        assert_eq!(
            per_time(Some("rad/s"), Some("s")).as_deref(),
            Some("rad/s²")
        );
        assert_eq!(per_time(Some("m"), None), None);
    }
}

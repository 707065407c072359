//! The small text grammar of the scene's descriptive parameters (`plate.clamp`,
//! `obstacle.lower_profile`, `obstacle.upper_profile`): items separated at the top level by a
//! separator, each item a name with an optional parenthesised argument list, `name(a, b)` or
//! `name(key = value, …)`. One grammar keeps every such parameter settable as one string from an
//! FMU host, a scene file or an SSV parameter set (docs/usage.md, "Profiles and clamps").

/// A parsed item: `name` and its arguments, empty without parentheses.
#[derive(Clone, Debug, PartialEq)]
pub struct Call<'a> {
    /// The item's name, trimmed.
    pub name: &'a str,
    /// The text between the parentheses, trimmed; `None` without parentheses.
    pub arguments: Option<&'a str>,
}

/// Splits `text` at every `separator` outside parentheses; each part trimmed, empty parts kept
/// (the caller decides whether an empty item is an error). `Err` names an unbalanced parenthesis.
pub fn split_top_level(text: &str, separator: char) -> Result<Vec<&str>, String> {
    let mut parts = Vec::new();
    let mut depth = 0usize;
    let mut start = 0;
    for (i, c) in text.char_indices() {
        match c {
            '(' => depth += 1,
            ')' => {
                depth = depth
                    .checked_sub(1)
                    .ok_or_else(|| format!("has a ')' without its '(' at character {}", i + 1))?;
            }
            c if c == separator && depth == 0 => {
                parts.push(text[start..i].trim());
                start = i + c.len_utf8();
            }
            _ => {}
        }
    }
    if depth > 0 {
        return Err("has a '(' that is never closed".to_string());
    }
    parts.push(text[start..].trim());
    Ok(parts)
}

/// Parses one item `name` or `name(arguments)`.
pub fn parse_call(item: &str) -> Result<Call<'_>, String> {
    let item = item.trim();
    match item.find('(') {
        None => Ok(Call {
            name: item,
            arguments: None,
        }),
        Some(open) => {
            let inner = item[open + 1..]
                .strip_suffix(')')
                .ok_or_else(|| format!("has text after the ')' of '{item}'"))?;
            Ok(Call {
                name: item[..open].trim(),
                arguments: Some(inner.trim()),
            })
        }
    }
}

/// Parses a finite number, naming `what` when it is not one.
pub fn number(text: &str, what: &str) -> Result<f64, String> {
    let text = text.trim();
    match text.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(x) => Err(format!("has {what} = {x}, which is not finite")),
        Err(_) => Err(format!("has {what} = '{text}', which is not a number")),
    }
}

/// The `key = value` arguments of an item, each key among `known` at most once; `Err` names an
/// unknown or repeated key or a value that is not a finite number.
pub fn keyword_numbers<'a>(
    arguments: &'a str,
    known: &[&str],
    item: &str,
) -> Result<Vec<(&'a str, f64)>, String> {
    let mut values: Vec<(&str, f64)> = Vec::new();
    for part in split_top_level(arguments, ',')? {
        if part.is_empty() {
            continue;
        }
        let (key, value) = part
            .split_once('=')
            .ok_or_else(|| format!("has '{part}' in {item}, where key = value was expected"))?;
        let key = key.trim();
        if !known.contains(&key) {
            return Err(format!(
                "has an unknown argument '{key}' in {item} (known: {})",
                known.join(", ")
            ));
        }
        if values.iter().any(|(k, _)| *k == key) {
            return Err(format!("gives {key} twice in {item}"));
        }
        values.push((key, number(value, &format!("{key} of {item}"))?));
    }
    Ok(values)
}

/// The value of `key` among parsed keyword arguments, or `default` when absent (`None`: the
/// argument is required, and its absence is an error naming it).
pub fn argument(
    values: &[(&str, f64)],
    key: &str,
    default: Option<f64>,
    item: &str,
) -> Result<f64, String> {
    values
        .iter()
        .find(|(k, _)| *k == key)
        .map(|&(_, v)| v)
        .or(default)
        .ok_or_else(|| format!("lacks {key} in {item}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn top_level_split_ignores_separators_inside_parentheses() {
        assert_eq!(
            split_top_level("a(1, 2), b , c(3)", ',').unwrap(),
            vec!["a(1, 2)", "b", "c(3)"]
        );
        assert!(split_top_level("a(1", ',')
            .unwrap_err()
            .contains("never closed"));
        assert!(split_top_level("a)1", ',').unwrap_err().contains("')'"));
    }

    #[test]
    fn calls_and_keyword_arguments_parse_with_errors_naming_the_item() {
        let call = parse_call(" disc( x = 1, y=2 ) ").unwrap();
        assert_eq!(call.name, "disc");
        let values = keyword_numbers(call.arguments.unwrap(), &["x", "y"], "stop 1").unwrap();
        assert_eq!(argument(&values, "y", None, "stop 1").unwrap(), 2.0);
        assert_eq!(argument(&values, "z", Some(5.0), "stop 1").unwrap(), 5.0);
        assert!(argument(&values, "z", None, "stop 1")
            .unwrap_err()
            .contains("lacks z in stop 1"));
        let err = keyword_numbers("x=1, w=2", &["x"], "stop 2").unwrap_err();
        assert!(err.contains("unknown argument 'w' in stop 2"), "{err}");
        let err = keyword_numbers("x=1, x=2", &["x"], "stop 2").unwrap_err();
        assert!(err.contains("x twice"), "{err}");
        let err = keyword_numbers("x=NaN", &["x"], "stop 2").unwrap_err();
        assert!(err.contains("not finite"), "{err}");
        let err = keyword_numbers("x=abc", &["x"], "stop 2").unwrap_err();
        assert!(err.contains("not a number"), "{err}");
        assert!(parse_call("disc(x=1) y").is_err());
    }
}

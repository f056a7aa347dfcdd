//! Where a validator key (`body[2].torque[0]`, `simulation.dt`) sits in the
//! scenario text, so bad-input messages can give `file:line:column`.

use toml_edit::{Item, Table, TableLike, Value};

enum Node<'a> {
    Item(&'a Item),
    Table(&'a Table),
    Value(&'a Value),
}

impl<'a> Node<'a> {
    fn table(&self) -> Option<&'a dyn TableLike> {
        match *self {
            Node::Item(i) => i.as_table_like(),
            Node::Table(t) => Some(t),
            Node::Value(Value::InlineTable(t)) => Some(t),
            Node::Value(_) => None,
        }
    }

    /// Element `i` of an array of tables or of an array value, and its offset.
    fn index(&self, i: usize) -> Option<(Node<'a>, Option<usize>)> {
        let array = match *self {
            Node::Item(Item::ArrayOfTables(a)) => {
                let t = a.get(i)?;
                return Some((Node::Table(t), t.span().map(|s| s.start)));
            }
            Node::Item(Item::Value(Value::Array(a))) | Node::Value(Value::Array(a)) => a,
            _ => return None,
        };
        let v = array.get(i)?;
        Some((Node::Value(v), v.span().map(|s| s.start)))
    }
}

/// 1-based line and column of `key` in the TOML `text`. A key that is not in
/// the text (a missing field) gets the deepest table or element on its path
/// that is, e.g. its `[[body]]` header; `None` if nothing on the path is.
pub fn locate(text: &str, key: &str) -> Option<(usize, usize)> {
    let doc = toml_edit::ImDocument::parse(text).ok()?;
    let mut node = Node::Item(doc.as_item());
    let mut at: Option<usize> = None;
    'path: for seg in key.split('.') {
        let mut parts = seg.split(['[', ']']).filter(|s| !s.is_empty());
        let Some(name) = parts.next() else { break };
        let Some((k, item)) = node.table().and_then(|t| t.get_key_value(name)) else {
            break;
        };
        at = k.span().or_else(|| item.span()).map(|s| s.start).or(at);
        node = Node::Item(item);
        for p in parts {
            let Some((next, off)) = p.parse().ok().and_then(|i| node.index(i)) else {
                break 'path;
            };
            at = off.or(at);
            node = next;
        }
    }
    Some(line_col(text, at?))
}

/// 1-based line and column (in characters) of the byte `offset` of `text`.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let mut at = offset.min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

#[cfg(test)]
mod tests {
    use super::locate;

    const TEXT: &str = "[simulation]\ndt = 1e-4\nt_end = 1.0\n\n[[body]]\nshape = \"fibre\"\n\n[[body]]\n  density = -1.0\ntorque = [\"0\", \"t\", \"x\"]\n";

    #[test]
    fn keys_elements_and_missing_keys() {
        assert_eq!(locate(TEXT, "simulation.t_end"), Some((3, 1)));
        assert_eq!(locate(TEXT, "body[1].density"), Some((9, 3)));
        assert_eq!(locate(TEXT, "body[1].torque[2]"), Some((10, 21)));
        // Missing: the body's header, the section's key, nothing.
        assert_eq!(locate(TEXT, "body[0].length"), Some((5, 1)));
        assert_eq!(locate(TEXT, "simulation.every"), Some((1, 2)));
        assert_eq!(locate(TEXT, "box.min"), None);
        assert_eq!(locate("[simulation\n", "simulation.dt"), None);
    }
}

//! The pre-check: a pass over the parsed TOML document, before serde, that
//! finds every problem a table of known keys ([`super::keys`]) can judge
//! (a table or key it does not know, with the closest known one; a key
//! missing, mistyped or out of range; a name an enumerated key does not
//! take; the rules that tie the keys of one body together) and reports
//! them all in one message, in file order, each with `file:line:column`,
//! its unit and the fix. A file that is not TOML gets its syntax error in
//! the same style. It also warns (never refuses) when a material or size
//! value lies outside the range of engineering practice, naming the unit
//! it may have been meant in; the warnings join any error the load ends
//! in, since a value in the wrong unit is often its cause.
//!
//! The build still checks everything (and what needs the whole scene: the
//! box, overlaps, the reference); serde stays behind both as a backstop.

use super::check;
use super::keys::{self, Facts, Form, Key, Kind, Need, TableSpec, TABLES};
use super::spell;
use crate::error::{Error, Result};
use crate::fmt::short;
use crate::scenario::file::TorqueComponent;
use toml_edit::{Item, TableLike, Value};

/// One problem: the key (`body[0].young`) and what is wrong with it.
struct Problem {
    key: String,
    message: String,
}

/// A value outside the range of engineering practice.
pub(super) struct Warning {
    /// `file:line:column: key: message`, as printed.
    pub(super) shown: String,
    /// What is implausible and the unit it may have been meant in.
    pub(super) message: String,
}

/// Check `text` (the scenario file `source`) against the key table. `Ok`
/// holds the warnings; `Err` every problem in one bad-input error.
pub(super) fn precheck(text: &str, source: &str) -> Result<Vec<Warning>> {
    let doc = match toml_edit::ImDocument::parse(text) {
        Ok(doc) => doc,
        Err(e) => return Err(syntax(&e, text, source)),
    };
    let root = doc.as_table();
    let mut pass = Pass::default();
    let bodies: Vec<&toml_edit::Table> = root
        .get("body")
        .and_then(Item::as_array_of_tables)
        .map(|a| a.iter().collect())
        .unwrap_or_default();
    let contacts = root.contains_key("box") || root.contains_key("bodies") || bodies.len() > 1;
    let used: Vec<&str> = bodies
        .iter()
        .filter_map(|b| b.get("material").and_then(Item::as_str))
        .collect();
    // Unknown tables first: a misspelt `[simulaton]` is named as such, not
    // also as a missing `[simulation]`.
    let mut meant: Vec<&str> = vec![];
    for (name, item) in root.iter() {
        if !TABLES.iter().any(|t| t.name == name) {
            meant.extend(pass.unknown_root(name, item));
        }
    }
    for spec in TABLES {
        match root.get(spec.name) {
            None if spec.required && !meant.contains(&spec.name) => pass.missing_table(spec),
            None => {}
            Some(item) => pass.table(spec, item, contacts, &used),
        }
    }
    for (i, b) in bodies.iter().enumerate() {
        pass.body_rules(root, i, b, contacts);
    }
    let at = |key: &str| super::locate(text, key);
    let shown = |l: Option<(usize, usize)>, p: &Problem| {
        let l = l.map_or(String::new(), |(l, c)| format!(":{l}:{c}"));
        format!("{source}{l}: {}: {}", p.key, p.message)
    };
    let warnings: Vec<Warning> = pass
        .warnings
        .iter()
        .map(|p| Warning {
            shown: shown(at(&p.key), p),
            message: p.message.clone(),
        })
        .collect();
    // In file order; what has no place in the file (none so far) last.
    let mut problems: Vec<(Option<(usize, usize)>, Problem)> =
        pass.problems.into_iter().map(|p| (at(&p.key), p)).collect();
    problems.sort_by_key(|(l, _)| l.unwrap_or((usize::MAX, 0)));
    let error = match problems.as_slice() {
        [] => return Ok(warnings),
        [(line, p)] => Error::BadInput {
            file: source.to_string(),
            line: *line,
            key: p.key.clone(),
            message: p.message.clone(),
        },
        _ => {
            let mut tables: Vec<&str> = vec![];
            for (_, p) in &problems {
                let t = p.key.split('.').next().unwrap_or(&p.key);
                let t = if t == "material" {
                    p.key.rsplit_once('.').map_or(t, |(head, _)| head)
                } else {
                    t
                };
                if !tables.contains(&t) {
                    tables.push(t);
                }
            }
            let lines: Vec<String> = problems
                .iter()
                .map(|(l, p)| format!("  {}", shown(*l, p).replace('\n', "\n    ")))
                .collect();
            Error::bad(
                source,
                tables.join(", "),
                format!(
                    "{} problems; fix them all, then run again:\n{}",
                    problems.len(),
                    lines.join("\n")
                ),
            )
        }
    };
    Err(with_warnings(error, &warnings))
}

/// `error` with the pre-check's `warnings` under it, each on its own line
/// (but for one the message already gives: a fibre that fits no box names
/// its size in the wrong unit itself).
pub(super) fn with_warnings(error: Error, warnings: &[Warning]) -> Error {
    match error {
        Error::BadInput {
            file,
            line,
            key,
            mut message,
        } => {
            for w in warnings {
                if !message.contains(&w.message) {
                    message += &format!("\n  warning: {}", w.shown);
                }
            }
            Error::BadInput {
                file,
                line,
                key,
                message,
            }
        }
        e => e,
    }
}

/// A file that is not TOML: the parser's message at its line and column.
fn syntax(e: &toml_edit::TomlError, text: &str, source: &str) -> Error {
    let what: Vec<&str> = e
        .message()
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    Error::BadInput {
        file: source.to_string(),
        line: e.span().map(|s| super::locate::line_col(text, s.start)),
        key: "TOML".into(),
        message: format!(
            "{}; fix the line (https://toml.io describes the format; scenarios/ has examples)",
            what.join(", ")
        ),
    }
}

#[derive(Default)]
struct Pass {
    problems: Vec<Problem>,
    warnings: Vec<Problem>,
}

/// A number: TOML floats and integers both.
fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Float(f) => Some(*f.value()),
        Value::Integer(i) => Some(*i.value() as f64),
        _ => None,
    }
}

/// `n` numbers.
fn numbers(v: &Value, n: usize) -> Option<Vec<f64>> {
    let a = v.as_array()?;
    (a.len() == n)
        .then(|| a.iter().map(number).collect())
        .flatten()
}

/// The TOML value as written, for messages.
fn shown(item: &Item) -> String {
    match item {
        Item::Value(v) => {
            let mut bare = v.clone();
            bare.decor_mut().clear();
            format!("{} `{bare}`", v.type_name())
        }
        other => other.type_name().to_string(),
    }
}

impl Pass {
    fn problem(&mut self, key: String, message: impl Into<String>) {
        self.problems.push(Problem {
            key,
            message: message.into(),
        });
    }

    /// A root item that is no table of the scene: the table it is closest
    /// to (returned, so that table is not also reported missing), or the
    /// table a key of that name belongs in.
    fn unknown_root(&mut self, name: &str, item: &Item) -> Option<&'static str> {
        let table = spell::closest(name, TABLES.iter().map(|t| t.name))
            .and_then(|n| TABLES.iter().find(|t| t.name == n));
        let home = keys::KEYS.iter().find(|k| k.name == name);
        let written = match item {
            Item::ArrayOfTables(_) => format!("[[{name}]]"),
            Item::Table(_) => format!("[{name}]"),
            _ => format!("`{name}`"),
        };
        let message = match (table, home) {
            (Some(t), _) => format!(
                "unknown table {written}; did you mean {}, {}?",
                t.header(),
                t.meaning
            ),
            (None, Some(k)) => format!(
                "{written} is a key of [{}], not a table of its own; write it under [{}], e.g. `{} = {}`",
                k.table, k.table, k.name, k.example
            ),
            (None, None) => format!(
                "unknown table {written}; a scenario has the tables {} (`fibresim keys` describes them)",
                TABLES
                    .iter()
                    .map(|t| t.header())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        };
        self.problem(name.to_string(), message);
        table.map(|t| t.name)
    }

    fn missing_table(&mut self, spec: &TableSpec) {
        if spec.form == Form::Array {
            return self.problem(spec.name.into(), check::NO_BODIES);
        }
        let mut add = format!(
            "missing table {}; add it:\n{}",
            spec.header(),
            spec.header()
        );
        for k in keys::keys_of(spec.name).filter(|k| matches!(k.need, Need::Required)) {
            add += &format!("\n{} = {}   # {}", k.name, k.example, describe(k));
        }
        self.problem(spec.name.into(), add);
    }

    /// A table as it appears in the root, in its form.
    fn table(&mut self, spec: &TableSpec, item: &Item, contacts: bool, used: &[&str]) {
        match spec.form {
            Form::Single => match item.as_table_like() {
                Some(t) => self.keys(
                    spec.name,
                    spec.name,
                    t,
                    &Facts {
                        contacts,
                        closed_form: t
                            .get("closed_form")
                            .and_then(Item::as_str)
                            .map(str::to_string),
                        ..Facts::default()
                    },
                ),
                None => self.problem(
                    spec.name.into(),
                    format!(
                        "must be one table {}, not {}",
                        spec.header(),
                        item.type_name()
                    ),
                ),
            },
            Form::Array => match item.as_array_of_tables() {
                Some(a) => {
                    for (i, t) in a.iter().enumerate() {
                        let facts = Facts {
                            shape: t.get("shape").and_then(Item::as_str).map(str::to_string),
                            has_material: t.contains_key("material"),
                            contacts,
                            ..Facts::default()
                        };
                        self.keys(spec.name, &format!("{}[{i}]", spec.name), t, &facts);
                    }
                }
                None => self.problem(
                    spec.name.into(),
                    format!(
                        "write {} (two brackets, one table per {}), not {}",
                        spec.header(),
                        spec.name,
                        item.type_name()
                    ),
                ),
            },
            Form::Named => {
                let Some(t) = item.as_table_like() else {
                    return self.problem(
                        spec.name.into(),
                        format!("write {} tables, e.g. [{}.glass]", spec.header(), spec.name),
                    );
                };
                for (name, sub) in t.iter() {
                    match sub.as_table_like() {
                        Some(st) => {
                            let facts = Facts {
                                used: used.contains(&name),
                                contacts,
                                ..Facts::default()
                            };
                            self.keys(spec.name, &format!("{}.{name}", spec.name), st, &facts);
                        }
                        None => self.problem(
                            format!("{}.{name}", spec.name),
                            format!(
                                "write {} tables, e.g. [{}.glass] with density = 1100.0",
                                spec.header(),
                                spec.name
                            ),
                        ),
                    }
                }
            }
        }
    }

    /// Every key of one table instance at `prefix`: those it does not
    /// know, with the closest it knows; those it needs and lacks; and the
    /// value of each it has.
    fn keys(&mut self, table: &str, prefix: &str, t: &dyn TableLike, facts: &Facts) {
        // What each unknown key was probably meant to be.
        let mut meant: Vec<&str> = vec![];
        for (u, _) in t.iter().filter(|(k, _)| keys::key(table, k).is_none()) {
            let near = spell::closest(u, keys::keys_of(table).map(|k| k.name))
                .and_then(|n| keys::key(table, n));
            let message = match near {
                Some(k) => {
                    meant.push(k.name);
                    format!(
                        "unknown key `{u}`; did you mean `{}`, {}? e.g. `{} = {}`",
                        k.name,
                        describe(k),
                        k.name,
                        k.example
                    )
                }
                None => format!(
                    "unknown key `{u}`; the keys of {} are {} (`fibresim keys` describes them)",
                    TABLES
                        .iter()
                        .find(|t| t.name == table)
                        .map_or(format!("[{table}]"), TableSpec::header),
                    keys::keys_of(table)
                        .map(|k| k.name)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            };
            self.problem(format!("{prefix}.{u}"), message);
        }
        for k in keys::keys_of(table) {
            let at = format!("{prefix}.{}", k.name);
            match t.get(k.name) {
                None => {
                    let needed = match k.need {
                        Need::Required => true,
                        Need::Optional(_) => false,
                        Need::When { when, .. } => when(facts),
                    };
                    // A misspelt key was named above, with this one.
                    if needed && !meant.contains(&k.name) {
                        self.problem(
                            at,
                            format!(
                                "missing: {}; add e.g. `{} = {}`",
                                describe(k),
                                k.name,
                                k.example
                            ),
                        );
                    }
                }
                Some(item) => self.value(k, at, item, facts),
            }
        }
    }

    /// One value against its key's kind, and its typical range.
    fn value(&mut self, k: &Key, at: String, item: &Item, facts: &Facts) {
        let wrong = |what: &str| {
            format!(
                "invalid type: expected {what}, got {}; e.g. `{} = {}`",
                shown(item),
                k.name,
                k.example
            )
        };
        let v = item.as_value();
        let problem: Option<String> = match k.kind {
            Kind::Positive | Kind::Finite | Kind::NonNegative | Kind::NonZero | Kind::Poisson => {
                match v.and_then(number) {
                    None => Some(wrong("a number")),
                    Some(x) => {
                        let bad = match k.kind {
                            Kind::Positive => check::not_positive(x),
                            Kind::Poisson => check::not_poisson(x),
                            Kind::NonNegative => check::not_non_negative(x),
                            Kind::Finite => (!x.is_finite())
                                .then(|| format!("must be a finite number, got {}", short(x))),
                            _ => (!(x.is_finite() && x != 0.0)).then(|| {
                                format!("must be a finite number other than 0, got {}", short(x))
                            }),
                        };
                        if bad.is_none() {
                            self.typical(k, &at, x, facts);
                        }
                        bad
                    }
                }
            }
            Kind::Count => match v.and_then(Value::as_integer) {
                None => Some(wrong("an integer")),
                Some(n) if n < 1 => Some(check::EVERY_ZERO.into()),
                Some(_) => None,
            },
            Kind::Vec3 | Kind::Direction => match v.and_then(|v| numbers(v, 3)) {
                None => Some(wrong("three numbers [x, y, z]")),
                Some(x) => {
                    let x = [x[0], x[1], x[2]];
                    check::not_finite3(x).or_else(|| {
                        let zero = x.iter().map(|c| c * c).sum::<f64>().sqrt() < 1e-12;
                        (k.kind == Kind::Direction && zero).then(|| check::ZERO_AXIS.into())
                    })
                }
            },
            Kind::UnitQuaternion => match v.and_then(|v| numbers(v, 4)) {
                None => Some(wrong("four numbers [w, x, y, z]")),
                Some(q) => check::not_unit_quaternion(q.iter().map(|c| c * c).sum::<f64>().sqrt()),
            },
            Kind::Rotator | Kind::Shape | Kind::ClosedForm | Kind::OrientationBodies => {
                match v.and_then(Value::as_str) {
                    None => Some(wrong("a name in quotes")),
                    Some(name) => {
                        (!k.kind.names().contains(&name)).then(|| check::unknown_name(k.kind, name))
                    }
                }
            }
            Kind::Text => v
                .and_then(Value::as_str)
                .is_none()
                .then(|| wrong("text in quotes")),
            Kind::Torque => return self.torque(k, at, item),
        };
        if let Some(m) = problem {
            self.problem(at, m);
        }
    }

    /// A torque: three numbers or expressions, compiled as the build does.
    fn torque(&mut self, k: &Key, at: String, item: &Item) {
        let parts: Option<Vec<TorqueComponent>> = item
            .as_value()
            .and_then(Value::as_array)
            .filter(|a| a.len() == 3)
            .and_then(|a| {
                a.iter()
                    .map(|v| match v {
                        Value::String(s) => Some(TorqueComponent::Expr(s.value().clone())),
                        v => number(v).map(TorqueComponent::Number),
                    })
                    .collect()
            });
        let Some(parts) = parts else {
            return self.problem(
                at,
                format!(
                    "invalid type: expected three numbers or expressions in t, got {}; e.g. `{} = {}`",
                    shown(item),
                    k.name,
                    k.example
                ),
            );
        };
        let texts = [parts[0].text(), parts[1].text(), parts[2].text()];
        if let Err((c, m)) = crate::torque::PrescribedTorque::parse(&texts) {
            self.problem(format!("{at}[{c}]"), m);
        }
    }

    /// Warn when `x` lies outside the key's typical range, naming the
    /// units it would be typical in.
    fn typical(&mut self, k: &Key, at: &str, x: f64, facts: &Facts) {
        // Sizes are judged for fibres only (test case 3's sphere is 2 m).
        if k.table == "body"
            && matches!(k.name, "diameter" | "length")
            && facts.shape.as_deref() != Some("fibre")
        {
            return;
        }
        if let Some(hint) = k.unit_hint(x) {
            self.warnings.push(Problem {
                key: at.to_string(),
                message: hint,
            });
        }
    }

    /// Rules that tie keys of one body together (the build checks them too).
    fn body_rules(
        &mut self,
        root: &toml_edit::Table,
        i: usize,
        b: &toml_edit::Table,
        contacts: bool,
    ) {
        let at = |k: &str| format!("body[{i}].{k}");
        let shape = b.get("shape").and_then(Item::as_str);
        if shape == Some("rigid") {
            self.rigid_rules(i, b, contacts);
        } else if matches!(shape, Some("fibre" | "sphere")) {
            for k in ["mass", "inertia"]
                .into_iter()
                .filter(|k| b.contains_key(k))
            {
                self.problem(at(k), check::rigid_only(k));
            }
        }
        if shape == Some("sphere") && b.contains_key("length") {
            self.problem(at("length"), check::SPHERE_LENGTH);
        }
        if let Some(m) = b.get("material") {
            if ["density", "young", "poisson"]
                .iter()
                .any(|k| b.contains_key(k))
            {
                self.problem(at("material"), check::MATERIAL_AND_INLINE);
            } else if let Some(name) = m.as_str() {
                let known: Vec<&str> = root
                    .get("material")
                    .and_then(Item::as_table_like)
                    .map(|t| t.iter().map(|(k, _)| k).collect())
                    .unwrap_or_default();
                if !known.contains(&name) {
                    self.problem(at("material"), check::unknown_material(name, &known));
                }
            }
        }
        if b.contains_key("axis") && b.contains_key("quaternion") {
            self.problem(at("axis"), check::AXIS_AND_QUATERNION);
        }
    }

    /// The rules of a `rigid` body (the build checks them too): mass and
    /// inertia only, no contacts, moments that a body can have.
    fn rigid_rules(&mut self, i: usize, b: &toml_edit::Table, contacts: bool) {
        let at = |k: &str| format!("body[{i}].{k}");
        if contacts {
            self.problem(at("shape"), check::RIGID_CONTACTS);
        }
        for k in check::NOT_FOR_RIGID {
            if b.contains_key(k) {
                self.problem(at(k), check::not_for_rigid(k));
            }
        }
        let Some(m) = b
            .get("inertia")
            .and_then(Item::as_value)
            .and_then(|v| numbers(v, 3))
        else {
            return;
        };
        if !m.iter().all(|x| x.is_finite()) {
            return; // reported with the value
        }
        let mut positive = true;
        for (k, &x) in m.iter().enumerate() {
            if let Some(why) = check::not_positive(x) {
                self.problem(at(&format!("inertia[{k}]")), why);
                positive = false;
            }
        }
        if positive {
            if let Some(why) = check::not_inertia([m[0], m[1], m[2]]) {
                self.problem(at("inertia"), why);
            }
        }
    }
}

/// What a key is, with its unit and range: `Young's modulus of the walls (Pa, > 0)`.
fn describe(k: &Key) -> String {
    let unit = if k.unit.is_empty() {
        String::new()
    } else {
        format!("{}, ", k.unit)
    };
    format!("{} ({unit}{})", k.meaning, k.kind.allowed())
}

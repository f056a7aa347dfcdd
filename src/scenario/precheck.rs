//! The pre-check: a pass over the parsed TOML document, before serde, that
//! finds every missing, mistyped or invalid key a table of known keys
//! ([`super::keys`]) can judge, and reports them all in one message, each
//! with `file:line:column`, its unit and the fix. It also warns (never
//! refuses) when a material or size value lies outside the range of
//! engineering practice, naming the unit it may have been meant in.
//!
//! What it does not know (a table or key added to the serde mirror without
//! a line in the key table, a shape it has no line for) it leaves to serde
//! and to the build, which still check everything.

use super::check;
use super::keys::{self, Facts, Form, Key, Kind, Need, TableSpec, TABLES};
use crate::error::{Error, Result};
use crate::scenario::file::TorqueComponent;
use toml_edit::{Item, TableLike, Value};

/// One problem: the key (`body[0].young`) and what is wrong with it.
struct Problem {
    key: String,
    message: String,
}

/// Check `text` (the scenario file `source`) against the key table. `Ok`
/// holds the warnings (`file:line:col: key: ...`); `Err` every problem in
/// one bad-input error. A document that is not TOML passes, for serde to
/// report with its own position.
pub(super) fn precheck(text: &str, source: &str) -> Result<Vec<String>> {
    let Ok(doc) = toml_edit::ImDocument::parse(text) else {
        return Ok(vec![]);
    };
    let root = doc.as_table();
    let mut pass = Pass {
        problems: vec![],
        warnings: vec![],
    };
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
    for spec in TABLES {
        match root.get(spec.name) {
            None if spec.required => pass.missing_table(spec),
            None => {}
            Some(item) => pass.table(spec, item, contacts, &used),
        }
    }
    for (i, b) in bodies.iter().enumerate() {
        pass.body_rules(root, i, b, contacts);
    }
    let locate =
        |key: &str| super::locate(text, key).map_or(String::new(), |(l, c)| format!(":{l}:{c}"));
    let warnings = pass
        .warnings
        .iter()
        .map(|p| format!("{source}{}: {}: {}", locate(&p.key), p.key, p.message))
        .collect();
    match pass.problems.len() {
        0 => Ok(warnings),
        1 => {
            let p = &pass.problems[0];
            Err(Error::bad(source, &p.key, &p.message).located(text))
        }
        n => {
            let mut tables: Vec<&str> = vec![];
            for p in &pass.problems {
                let t = p.key.split('.').next().unwrap_or(&p.key);
                let t = if t.starts_with("material") {
                    p.key.rsplit_once('.').map_or(t, |(head, _)| head)
                } else {
                    t
                };
                if !tables.contains(&t) {
                    tables.push(t);
                }
            }
            let lines: Vec<String> = pass
                .problems
                .iter()
                .map(|p| {
                    format!(
                        "  {source}{}: {}: {}",
                        locate(&p.key),
                        p.key,
                        p.message.replace('\n', "\n    ")
                    )
                })
                .collect();
            Err(Error::bad(
                source,
                tables.join(", "),
                format!(
                    "{n} problems; fix them all, then run again:\n{}",
                    lines.join("\n")
                ),
            )
            .located(text))
        }
    }
}

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

/// Edit distance of two short keys (a misspelt key is a hint, not a check).
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let next = (prev + usize::from(ca != cb))
                .min(row[j] + 1)
                .min(row[j + 1] + 1);
            prev = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

impl Pass {
    fn problem(&mut self, key: String, message: impl Into<String>) {
        self.problems.push(Problem {
            key,
            message: message.into(),
        });
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

    /// Every known key of one table instance at `prefix`.
    fn keys(&mut self, table: &str, prefix: &str, t: &dyn TableLike, facts: &Facts) {
        let unknown: Vec<&str> = t
            .iter()
            .map(|(k, _)| k)
            .filter(|k| keys::key(table, k).is_none())
            .collect();
        for k in keys::keys_of(table) {
            let at = format!("{prefix}.{}", k.name);
            match t.get(k.name) {
                None => {
                    let needed = match k.need {
                        Need::Required => true,
                        Need::Optional(_) => false,
                        Need::When { when, .. } => when(facts),
                    };
                    if !needed {
                    } else if let Some(u) = unknown.iter().find(|u| distance(u, k.name) <= 2) {
                        // Said where the misspelt key is.
                        self.problem(
                            format!("{prefix}.{u}"),
                            format!(
                                "unknown field `{u}`; did you mean `{}`, {}? e.g. `{} = {}`",
                                k.name,
                                describe(k),
                                k.name,
                                k.example
                            ),
                        );
                    } else {
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
            Kind::Positive | Kind::Finite | Kind::NonZero | Kind::Poisson => {
                match v.and_then(number) {
                    None => Some(wrong("a number")),
                    Some(x) => {
                        let bad = match k.kind {
                            Kind::Positive => check::not_positive(x),
                            Kind::Poisson => check::not_poisson(x),
                            Kind::Finite => (!x.is_finite())
                                .then(|| format!("must be a finite number, got {x}")),
                            _ => (!(x.is_finite() && x != 0.0))
                                .then(|| format!("must be a finite number other than 0, got {x}")),
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
            Kind::Rotator => match v.and_then(Value::as_str) {
                None => Some(wrong("a rotator name")),
                Some(name) => crate::integrate::rotate::RotatorKind::from_name(name)
                    .is_none()
                    .then(|| check::unknown_rotator(name)),
            },
            // Shapes it has no line for are serde's to judge.
            Kind::Shape => v
                .and_then(Value::as_str)
                .is_none()
                .then(|| wrong("a shape name")),
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
        let Some(r) = k.typical else { return };
        // Sizes are judged for fibres only (test case 3's sphere is 2 m).
        if k.table == "body"
            && matches!(k.name, "diameter" | "length")
            && facts.shape.as_deref() != Some("fibre")
        {
            return;
        }
        if (r.lo..=r.hi).contains(&x) {
            return;
        }
        let side = if x < r.lo { "below" } else { "above" };
        let meant: Vec<(&str, f64)> = r
            .units
            .iter()
            // Shifted in decimal, so 10 µm is 1e-5 exactly as typed.
            .map(|&(u, p)| (u, format!("{x}e{p}").parse::<f64>().unwrap_or(f64::NAN)))
            .filter(|(_, si)| (r.lo..=r.hi).contains(si))
            .collect();
        let fix = if meant.is_empty() {
            format!("check the value; it is read in {}", k.unit)
        } else {
            let said: Vec<String> = meant.iter().map(|(u, _)| format!("{x} {u}")).collect();
            let write: Vec<String> = meant.iter().map(|(_, si)| format!("{si:e}")).collect();
            format!(
                "if you meant {}, write {} (values are read in {})",
                said.join(" or "),
                write.join(" or "),
                k.unit
            )
        };
        self.warnings.push(Problem {
            key: at.to_string(),
            message: format!(
                "{x} {} is {side} the range of {} ({:e} to {:e} {}); {fix}",
                k.unit, r.what, r.lo, r.hi, k.unit
            ),
        });
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
        if shape == Some("sphere") {
            if b.contains_key("length") {
                self.problem(at("length"), check::SPHERE_LENGTH);
            }
            if contacts {
                self.problem(at("shape"), check::SPHERE_CONTACTS);
            }
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

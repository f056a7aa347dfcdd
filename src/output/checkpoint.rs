//! Checkpoints: everything needed to continue a run bit for bit.
//!
//! Floats are stored as their IEEE-754 bit patterns (hex), so a resumed run
//! continues from exactly the same numbers and NaN statistics survive.
//!
//! A checkpoint records the run's identity: the scenario text (embedded, so
//! a later edit of the file cannot change a resumed run) with its hash, δt,
//! the rotator, the row cadence, the guards, the planned number of steps,
//! the optional outputs' cadences and the settle test and restitution of a
//! damped run. Each observer records its output files with their marks
//! (length and tail hash, [`super::mark`]; cut back to the length on
//! resume, refused if the bytes differ) and its own state, by name.
//!
//! A scene whose contact law reads velocities (damped: `[contact]
//! restitution < 1`; frictional: `friction` or `wall_friction > 0`) also
//! stores what its step carries between steps beyond the states: the
//! force stage saw the half-step velocities, so its forces cannot be
//! recomputed from the full-step states. That is the last total contact
//! force and torque per body (48 bytes per body, in the states file) and
//! the ledger of the non-conservative loads (`done`, `dissipated`: two
//! numbers in the JSON, with the restitution and the friction the run
//! used). A frictional scene also stores each touching contact's record
//! (its tangential spring, its point's place and weight,
//! `contact/history.rs`) in the states file. A frictionless checkpoint
//! has no record section: its files are those of the two previous formats
//! but for the format's name, and both are still read; a frictional one
//! resumes from the previous format, whose records have no place.

use crate::body::BodyState;
use crate::contact::history::History;
use crate::contact::tangential::Friction;
use crate::error::{Error, Result};
use crate::integrate::rotate::Rotator;
use crate::integrate::step::World;
use crate::run::observer::Observer;
use crate::run::stats::RunStats;
use crate::scenario::{Ids, Scene};
use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The format this version writes and reads.
pub const FORMAT: &str = "fibresim-checkpoint-7";

/// The previous format, still read: the same files but for the contacts'
/// records, which hold the spring without its point's place (a body
/// pair's record then goes to the point of its own rank once, as that
/// format's runs matched them; `contact/history.rs`).
pub const FORMAT_WITHOUT_PLACES: &str = "fibresim-checkpoint-6";

/// The format before, still read: the same files without the contacts'
/// records, which only a frictional scene needs (refused there).
pub const FORMAT_WITHOUT_RECORDS: &str = "fibresim-checkpoint-5";

#[derive(Debug, Clone, Serialize, Deserialize)]
/// A checkpoint (`checkpoint.json`).
pub struct Checkpoint {
    /// [`FORMAT`].
    pub format: String,
    /// Where the scenario came from.
    pub scenario_source: String,
    /// The scenario text, as read.
    pub scenario_text: String,
    /// Its 64-bit FNV-1a hash (hex): a checkpoint whose scenario was
    /// edited after it was written is refused.
    pub scenario_fnv: String,
    /// The rotator's name.
    pub rotator: String,
    /// δt, bits.
    pub dt: String,
    /// Output cadence of the run's rows.
    pub every: u64,
    /// Guards (energy %, overlap ratio), bits.
    pub guards: [String; 2],
    /// The steps the run was to take: a resumed run continues to them
    /// unless `--t-end` says otherwise.
    pub steps_planned: u64,
    /// Completed steps; the time is `step · δt` (informative copy in `t`).
    pub step: u64,
    /// The time of `step`, s (informative).
    pub t: f64,
    /// The states file beside this one ([`states`]): every body's id and
    /// state, and the rotator's per-body state, as raw bits.
    pub states_file: String,
    /// Its length in bytes and its 64-bit FNV-1a hash (hex): a states file
    /// from another checkpoint, or a torn one, is refused.
    pub states_bytes: u64,
    /// (See `states_bytes`.)
    pub states_fnv: String,
    /// Global body ids, in the order of `states` (in the states file).
    #[serde(skip)]
    pub ids: Ids,
    /// Every body's state (in the states file).
    #[serde(skip)]
    pub states: Vec<BodyState>,
    /// The rotator's per-body auxiliary state, flat (in the states file).
    #[serde(skip)]
    pub aux: Vec<f64>,
    /// [`RunStats::to_array`], bits.
    pub run_stats: Vec<String>,
    /// Each output file by name (relative to the output folder), with its
    /// mark at the checkpoint.
    pub outputs: BTreeMap<String, super::mark::Mark>,
    /// Each observer's own state by its name, bits.
    pub observers: BTreeMap<String, Vec<String>>,
    /// Damped or frictional scenes only: the restitution, the friction and
    /// the ledger of the non-conservative loads.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<DampingPart>,
    /// Damped or frictional scenes only: the last force stage's contact
    /// force and torque per body, `[F, τ]` by body in the order of `states`
    /// (in the states file).
    #[serde(skip)]
    pub loads: Vec<[DVec3; 2]>,
    /// Frictional scenes only: the touching contacts' records (in the
    /// states file).
    #[serde(skip)]
    pub(crate) history: History,
    /// The fibre pairs' memories of their last end-involved scans that
    /// change what the kernels answer (`contact/memory.rs`), by pair (in
    /// the states file).
    #[serde(skip)]
    pub memory: Vec<crate::contact::memory::Entry>,
    /// `fibresim settle` runs only: the settle test.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub settle: Option<SettlePart>,
}

/// The settle test of a `fibresim settle` checkpoint.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SettlePart {
    /// The kinetic-energy threshold per fibre, J, bits.
    pub ke_per_fibre: String,
    /// Steps between two tests.
    pub check_every: u64,
}

impl SettlePart {
    /// The part of `s`.
    pub fn of(s: crate::run::Settle) -> Self {
        SettlePart {
            ke_per_fibre: bits(s.ke_per_body),
            check_every: s.every,
        }
    }

    /// The threshold, J per fibre.
    pub fn ke_per_fibre(&self) -> Result<f64> {
        unbits(&self.ke_per_fibre, "settle.ke_per_fibre")
    }
}

/// The part of a checkpoint's JSON of a scene whose contact law reads
/// velocities (damped or frictional scenes only), bits.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct DampingPart {
    /// The restitution the run used: fibre–fibre, fibre–wall (damped
    /// scenes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<[String; 2]>,
    /// The Coulomb coefficients the run used: body–body, body–wall
    /// (frictional scenes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<[String; 2]>,
    /// The ledger of the non-conservative loads between steps: the work of
    /// every earlier force stage, and the dissipated energy at the
    /// checkpoint's state, J.
    pub ledger: [String; 2],
    /// The energy the contacts' springs hold, J (frictional scenes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spring: Option<String>,
}

impl DampingPart {
    /// The restitution (`None`: elastic), or what is wrong with it.
    pub fn restitution(&self) -> Result<Option<crate::contact::damping::Restitution>> {
        self.restitution
            .as_ref()
            .map(|[fibre, wall]| {
                Ok(crate::contact::damping::Restitution {
                    fibre: unbits(fibre, "damping.restitution")?,
                    wall: unbits(wall, "damping.restitution")?,
                })
            })
            .transpose()
    }

    /// The friction (`None`: frictionless), or what is wrong with it.
    pub fn friction(&self) -> Result<Option<Friction>> {
        self.friction
            .as_ref()
            .map(|[body, wall]| {
                Ok(Friction {
                    body: unbits(body, "damping.friction")?,
                    wall: unbits(wall, "damping.friction")?,
                })
            })
            .transpose()
    }
}

pub use crate::integrate::world::DampedState;

/// A float as its 16-digit hex bit pattern.
pub fn bits(x: f64) -> String {
    format!("{:016x}", x.to_bits())
}

/// The float of a hex bit pattern; `what` names it in the error.
pub fn unbits(s: &str, what: &str) -> Result<f64> {
    u64::from_str_radix(s, 16).map(f64::from_bits).map_err(|_| {
        Error::bad(
            "checkpoint",
            what,
            format!("`{s}` is not a 16-digit hex float"),
        )
    })
}

fn unbits_all(v: &[String], what: &str) -> Result<Vec<f64>> {
    v.iter().map(|s| unbits(s, what)).collect()
}

/// The binary states file of a checkpoint (`checkpoint.<step>.states`): the magic
/// `FIBRESIM`, then little-endian `u64` body count and `u64` doubles of
/// rotator state per body, then per body its `u64` id and 13 `f64` (x, v,
/// q as w x y z, ω_b), then the rotator state; damped and frictional
/// scenes then add per body 6 `f64` (the contact force and torque, world);
/// then a `u64` count of pair memories and each as `u32` i, `u32` j and the
/// three `u16` of [`PairMemory::to_raw`]; frictional scenes last add the
/// touching contacts' records ([`History::encode`](crate::contact::history::History):
/// walls, then pairs, each a `u64` count and per contact `u32` a, `u32` b,
/// `u8` slot, the spring's three `f64` and its point's place, three `f64`).
/// 112 bytes per fibre for the shipped rotators (160 damped or
/// frictional), 14 per remembered pair, 57 per touching frictional
/// contact; floats are their exact bits.
pub mod states {
    use crate::body::{BodyState, RotState};
    use crate::contact::carry;
    use crate::contact::fibre_fibre::PairMemory;
    use crate::contact::history::History;
    use crate::contact::memory::{self, Entry};
    use crate::scenario::Ids;
    use glam::{DQuat, DVec3};

    /// The first bytes of a states file.
    pub const MAGIC: &[u8; 8] = b"FIBRESIM";

    /// 64-bit FNV-1a of `bytes`.
    pub fn fnv(bytes: &[u8]) -> u64 {
        let mut h = 0xcbf2_9ce4_8422_2325u64;
        for &b in bytes {
            h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
        h
    }

    /// The file's bytes (`loads`: empty, or one `[F, τ]` per body;
    /// `history`: a frictional scene's records).
    pub(crate) fn encode(
        ids: &Ids,
        states: &[BodyState],
        aux: &[f64],
        loads: &[[DVec3; 2]],
        memory: &[Entry],
        history: Option<&History>,
    ) -> Vec<u8> {
        let n = states.len();
        let per = aux.len().checked_div(n).unwrap_or(0);
        let mut out = Vec::with_capacity(24 + n * 112 + aux.len() * 8 + loads.len() * 48);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&(n as u64).to_le_bytes());
        out.extend_from_slice(&(per as u64).to_le_bytes());
        for (id, s) in ids.iter().zip(states) {
            out.extend_from_slice(&id.to_le_bytes());
            let q = s.rot.q;
            let w = s.rot.omega_b;
            for x in [
                s.x.x, s.x.y, s.x.z, s.v.x, s.v.y, s.v.z, q.w, q.x, q.y, q.z, w.x, w.y, w.z,
            ] {
                out.extend_from_slice(&x.to_bits().to_le_bytes());
            }
        }
        for &a in aux {
            out.extend_from_slice(&a.to_bits().to_le_bytes());
        }
        for [f, t] in loads {
            for x in [f.x, f.y, f.z, t.x, t.y, t.z] {
                out.extend_from_slice(&x.to_bits().to_le_bytes());
            }
        }
        carry::encode(memory.iter().copied(), &mut out);
        if let Some(h) = history {
            h.encode(&mut out);
        }
        out
    }

    /// What a states file holds: ids, states, rotator state, loads, pair
    /// memories, contacts' records.
    pub(crate) type Decoded = (
        Ids,
        Vec<BodyState>,
        Vec<f64>,
        Vec<[DVec3; 2]>,
        Vec<Entry>,
        History,
    );

    /// The ids, states, rotator state, (when `with_loads`: a damped or
    /// frictional scene's) loads, pair memories and (when `with_history`:
    /// a frictional scene's, for `walls` walls, with or without their
    /// places) contacts' records of a file's bytes, or what is wrong.
    pub(crate) fn decode(
        b: &[u8],
        with_loads: bool,
        with_history: Option<(usize, bool)>,
    ) -> Result<Decoded, String> {
        let word = |at: usize| -> Result<u64, String> {
            b.get(at..at + 8)
                .map(|w| u64::from_le_bytes(w.try_into().expect("8 bytes")))
                .ok_or_else(|| "the file is truncated".to_string())
        };
        if b.get(..8) != Some(&MAGIC[..]) {
            return Err("not a fibresim states file".into());
        }
        let n = word(8)? as usize;
        let per = word(16)? as usize;
        let loads_per = if with_loads { 48 } else { 0 };
        let before_memory = 24
            + n.saturating_mul(112)
            + n.saturating_mul(per).saturating_mul(8)
            + n.saturating_mul(loads_per);
        let (memory, after_memory) = {
            let tail = b.get(before_memory..).ok_or("the file is truncated")?;
            let (m, used) = carry::decode::<PairMemory>(tail, memory::WHAT, memory::valid_pair(n))?;
            (m, before_memory + used)
        };
        let (history, want) = match with_history {
            Some((walls, places)) => {
                let tail = &b[after_memory..];
                let (h, used) = History::decode(tail, n, walls, places)?;
                (h, after_memory + used)
            }
            None => (History::default(), after_memory),
        };
        if b.len() != want {
            return Err(format!(
                "{} bytes, expected {want} for {n} bodies and {} pair memories",
                b.len(),
                memory.len()
            ));
        }
        let f = |at: usize| f64::from_bits(word(at).expect("length checked"));
        let mut ids = Vec::with_capacity(n);
        let mut states = Vec::with_capacity(n);
        for k in 0..n {
            let at = 24 + k * 112;
            ids.push(word(at)?);
            let v = |i: usize| f(at + 8 + 8 * i);
            states.push(BodyState {
                x: DVec3::new(v(0), v(1), v(2)),
                v: DVec3::new(v(3), v(4), v(5)),
                rot: RotState {
                    q: DQuat::from_xyzw(v(7), v(8), v(9), v(6)),
                    omega_b: DVec3::new(v(10), v(11), v(12)),
                },
            });
        }
        let aux = (0..n * per).map(|i| f(24 + n * 112 + 8 * i)).collect();
        let at = 24 + n * 112 + n * per * 8;
        let v = |k: usize, i: usize| f(at + 48 * k + 8 * i);
        let loads = (0..if with_loads { n } else { 0 })
            .map(|k| {
                [
                    DVec3::new(v(k, 0), v(k, 1), v(k, 2)),
                    DVec3::new(v(k, 3), v(k, 4), v(k, 5)),
                ]
            })
            .collect();
        Ok((ids.into(), states, aux, loads, memory, history))
    }
}

impl Checkpoint {
    /// The driver's part of a checkpoint of `w` (observers add theirs).
    pub fn of<R: Rotator>(w: &World, stats: &RunStats) -> Self {
        let scene = w.scene;
        // A damped or frictional scene where nothing can touch has no
        // stage: nothing dissipated, no record.
        let ledger = w.contacts.as_ref().and_then(|c| c.damping_state());
        let damping = (scene.damping.is_some() || scene.friction.is_some()).then(|| DampingPart {
            restitution: scene.damping.map(|e| [bits(e.fibre), bits(e.wall)]),
            friction: scene.friction.map(|f| [bits(f.body), bits(f.wall)]),
            ledger: ledger.unwrap_or([0.0; 2]).map(bits),
            spring: scene.friction.map(|_| bits(w.spring_energy())),
        });
        let loads = match damping {
            Some(_) => w
                .force
                .iter()
                .zip(&w.torque)
                .map(|(&f, &t)| [f, t])
                .collect(),
            None => vec![],
        };
        Checkpoint {
            format: FORMAT.into(),
            scenario_source: scene.source.clone(),
            scenario_text: scene.text.clone(),
            scenario_fnv: format!("{:016x}", states::fnv(scene.text.as_bytes())),
            rotator: R::INFO.name.into(),
            dt: bits(scene.sim.dt()),
            every: scene.sim.every_or_default(),
            guards: [
                bits(scene.guards.energy_error_pct),
                bits(scene.guards.overlap_ratio),
            ],
            steps_planned: scene.sim.steps(),
            step: w.step,
            t: w.time(),
            states_file: String::new(),
            states_bytes: 0,
            states_fnv: String::new(),
            ids: scene.ids.clone(),
            states: w.states.clone(),
            aux: w.aux.clone(),
            run_stats: stats.to_array().map(bits).to_vec(),
            outputs: BTreeMap::new(),
            observers: BTreeMap::new(),
            history: w
                .contacts
                .as_ref()
                .and_then(|c| c.kept_history())
                .cloned()
                .unwrap_or_default(),
            damping,
            loads,
            memory: w
                .contacts
                .as_ref()
                .map_or_else(Vec::new, |c| c.memory_entries()),
            settle: None,
        }
    }

    /// Write the states file ([`states_file_name`]) and then `path`, each
    /// to a temporary name then renamed. The rename of `path` is the one
    /// moment the checkpoint changes: a kill at any point leaves the
    /// previous checkpoint.json with the states file it names, or the new
    /// pair. (The states file the previous checkpoint named is removed by
    /// [`CheckpointFile`] after the rename.)
    pub fn write(&mut self, path: &Path) -> Result<()> {
        let states_path = path.with_file_name(states_file_name(self.step));
        let bytes = states::encode(
            &self.ids,
            &self.states,
            &self.aux,
            &self.loads,
            &self.memory,
            self.damping
                .as_ref()
                .is_some_and(|d| d.friction.is_some())
                .then_some(&self.history),
        );
        self.states_file = states_path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        self.states_bytes = bytes.len() as u64;
        self.states_fnv = format!("{:016x}", states::fnv(&bytes));
        let text = serde_json::to_string_pretty(self).expect("checkpoint serialises");
        super::file::write_whole(&states_path, &bytes)?;
        super::file::write_whole(path, text.as_bytes())
    }

    /// Read and check a checkpoint file and its states file.
    pub fn read(path: &Path) -> Result<Self> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| {
            Error::bad(
                &file,
                "--resume",
                format!("cannot read the checkpoint: {e}; give the checkpoint.json a run wrote (--checkpoint-every N, or Ctrl-C)"),
            )
        })?;
        // The format first, so an older checkpoint gets a message that says so.
        let format = serde_json::from_str::<serde_json::Value>(&text)
            .ok()
            .and_then(|v| v.get("format").and_then(|f| f.as_str()).map(str::to_string));
        let known = [FORMAT, FORMAT_WITHOUT_PLACES, FORMAT_WITHOUT_RECORDS];
        if let Some(f) = format.as_ref().filter(|f| !known.contains(&f.as_str())) {
            return Err(Error::bad(
                &file,
                "format",
                format!("expected `{FORMAT}`, found `{f}`: this checkpoint was written by another version of fibresim; rerun from the start"),
            ));
        }
        let mut c: Checkpoint = serde_json::from_str(&text).map_err(|e| {
            Error::bad(
                &file,
                "--resume",
                format!("not a fibresim checkpoint: {e}; give the checkpoint.json a run wrote"),
            )
        })?;
        if format!("{:016x}", states::fnv(c.scenario_text.as_bytes())) != c.scenario_fnv {
            return Err(Error::bad(
                &file,
                "scenario_text",
                "does not match its hash `scenario_fnv`: the checkpoint was edited after it was written; resume from the checkpoint as the run wrote it, or rerun from the start",
            ));
        }
        let states_path = path.with_file_name(&c.states_file);
        let where_ = states_path.display().to_string();
        let bytes = std::fs::read(&states_path).map_err(|e| {
            Error::bad(
                &where_,
                "states_file",
                format!(
                    "cannot read the checkpoint's states: {e}; keep {} beside checkpoint.json",
                    c.states_file
                ),
            )
        })?;
        if bytes.len() as u64 != c.states_bytes
            || format!("{:016x}", states::fnv(&bytes)) != c.states_fnv
        {
            return Err(Error::bad(
                &where_,
                "states_file",
                "does not belong to this checkpoint (length or hash differs): it was written by another checkpoint, or the write was interrupted; resume from a complete checkpoint",
            ));
        }
        // Records of a frictional scene (in a box of six walls, or none).
        let records = c.damping.as_ref().is_some_and(|d| d.friction.is_some());
        let places = format.as_deref() != Some(FORMAT_WITHOUT_PLACES);
        (c.ids, c.states, c.aux, c.loads, c.memory, c.history) =
            states::decode(&bytes, c.damping.is_some(), records.then_some((6, places)))
                .map_err(|e| Error::bad(&where_, "states_file", e))?;
        Ok(c)
    }

    /// The recorded length of output `name`, or a bad-input error.
    pub fn output_len(&self, name: &str) -> Result<u64> {
        self.outputs.get(name).map(|m| m.bytes).ok_or_else(|| {
            Error::bad(
                "checkpoint",
                "outputs",
                format!(
                    "records no `{name}`, which this run writes: it does not match its scenario"
                ),
            )
        })
    }

    /// The cadence (steps) observer `name` saved as its state, if this
    /// checkpoint's run had that observer.
    pub fn cadence(&self, name: &str) -> Result<Option<u64>> {
        if !self.observers.contains_key(name) {
            return Ok(None);
        }
        match self.observer_state(name)?.as_slice() {
            [e] if *e >= 1.0 && e.fract() == 0.0 => Ok(Some(*e as u64)),
            _ => Err(Error::bad(
                "checkpoint",
                "observers",
                format!("`{name}` needs its cadence (1 whole number)"),
            )),
        }
    }

    /// Observer `name`'s saved state, as numbers.
    pub fn observer_state(&self, name: &str) -> Result<Vec<f64>> {
        let v = self.observers.get(name).ok_or_else(|| {
            Error::bad(
                "checkpoint",
                "observers",
                format!("has no state for `{name}`: it does not match its scenario"),
            )
        })?;
        unbits_all(v, "observers")
    }
}

/// The states (in storage order), the rotator's auxiliary state and the run
/// statistics of a checkpoint of `scene`, checked against it.
pub fn restore(
    c: &Checkpoint,
    scene: &Scene,
    aux_len: usize,
) -> Result<(Vec<BodyState>, Vec<f64>, RunStats)> {
    let n = scene.bodies.len();
    if c.states.len() != n || c.ids != scene.ids {
        return Err(Error::bad(
            "checkpoint",
            "states",
            "does not match its own scenario",
        ));
    }
    if c.aux.len() != aux_len * n {
        return Err(Error::bad(
            "checkpoint",
            "aux",
            format!(
                "has {} numbers; rotator `{}` keeps {aux_len} per body",
                c.aux.len(),
                c.rotator
            ),
        ));
    }
    let s = unbits_all(&c.run_stats, "run_stats")?;
    let stats: [f64; 11] = s
        .try_into()
        .map_err(|_| Error::bad("checkpoint", "run_stats", "needs 11 numbers"))?;
    Ok((c.states.clone(), c.aux.clone(), RunStats::from_array(stats)))
}

/// The part of a checkpoint of `scene` that a damped or frictional scene
/// needs (`None` for an elastic frictionless scene), checked against it: a
/// damped scene needs its restitution to the bit, a frictional one its
/// friction and its contacts' records.
pub fn restore_damping(c: &Checkpoint, scene: &Scene) -> Result<Option<DampedState>> {
    let reads_motion = scene.damping.is_some() || scene.friction.is_some();
    let part = match (reads_motion, &c.damping) {
        (false, None) => return Ok(None),
        (true, None) => return Err(Error::bad(
            "checkpoint",
            "damping",
            "holds no damping state, but its scene is damped or frictional ([contact] restitution < 1, friction > 0): it does not match its scenario; rerun from the start",
        )),
        (false, Some(_)) => return Err(Error::bad(
            "checkpoint",
            "damping",
            "holds a damping state, but its scene is elastic and frictionless: it does not match its scenario",
        )),
        (true, Some(part)) => part,
    };
    let saved = part.restitution()?;
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits();
    let agree = match (saved, scene.damping) {
        (None, None) => true,
        (Some(s), Some(e)) => same(s.fibre, e.fibre) && same(s.wall, e.wall),
        _ => false,
    };
    if !agree {
        let show = |r: Option<crate::contact::damping::Restitution>| {
            r.map_or("none (elastic)".to_string(), |r| {
                format!("{} (walls {})", r.fibre, r.wall)
            })
        };
        return Err(Error::bad(
            "checkpoint",
            "damping.restitution",
            format!(
                "was taken with restitution {}, the resumed scene has {}: a resumed run keeps its restitution; rerun from the start to change it",
                show(saved),
                show(scene.damping)
            ),
        ));
    }
    let friction = part.friction()?;
    match (friction, scene.friction) {
        (None, None) => {}
        (Some(s), Some(f)) if same(s.body, f.body) && same(s.wall, f.wall) => {}
        (None, Some(_)) => return Err(Error::bad(
            "checkpoint",
            "damping.friction",
            "holds no contact springs, but its scene is frictional: it was written by a fibresim that did not checkpoint frictional scenes; rerun from the start",
        )),
        _ => return Err(Error::bad(
            "checkpoint",
            "damping.friction",
            "was taken with another friction than the resumed scene's: a resumed run keeps its friction; rerun from the start to change it",
        )),
    }
    if c.loads.len() != scene.bodies.len() {
        return Err(Error::bad(
            "checkpoint",
            "states_file",
            format!(
                "holds {} contact loads for {} bodies",
                c.loads.len(),
                scene.bodies.len()
            ),
        ));
    }
    Ok(Some(DampedState {
        loads: c.loads.clone(),
        ledger: [
            unbits(&part.ledger[0], "damping.ledger")?,
            unbits(&part.ledger[1], "damping.ledger")?,
        ],
        history: friction.map(|_| c.history.clone()),
        spring: match (&part.spring, friction) {
            (Some(e), Some(_)) => unbits(e, "damping.spring")?,
            (None, Some(_)) => {
                return Err(Error::bad(
                    "checkpoint",
                    "damping.spring",
                    "is missing: a frictional checkpoint keeps its springs' energy; resume from a checkpoint as a run wrote it",
                ))
            }
            _ => 0.0,
        },
    }))
}

/// File name of the checkpoint inside the output folder.
pub const CHECKPOINT_FILE: &str = "checkpoint.json";

/// The states file of a checkpoint taken at `step`, beside
/// [`CHECKPOINT_FILE`]: named by its step, so that writing a checkpoint
/// never overwrites the states file that the current checkpoint.json names.
pub fn states_file_name(step: u64) -> String {
    format!("checkpoint.{step}.states")
}

/// Whether `name` is a [`states_file_name`].
pub fn is_states_file_name(name: &str) -> bool {
    name.strip_prefix("checkpoint.")
        .and_then(|n| n.strip_suffix(".states"))
        .is_some_and(|step| !step.is_empty() && step.bytes().all(|b| b.is_ascii_digit()))
}

/// The observer that writes `checkpoint.json` (last in the observer list, so
/// the checkpoint holds every other observer's part).
pub struct CheckpointFile {
    /// `checkpoint.json` in the output folder.
    pub path: PathBuf,
    /// The states file the current checkpoint.json names, once this run
    /// has written or resumed one.
    pub states_file: Option<String>,
}

impl Observer for CheckpointFile {
    fn checkpoint(&mut self, c: &mut Checkpoint) -> Result<()> {
        c.write(&self.path)?;
        let before = self.states_file.replace(c.states_file.clone());
        if let Some(old) = before.filter(|old| *old != c.states_file) {
            let old = self.path.with_file_name(old);
            if let Err(e) = std::fs::remove_file(&old) {
                if e.kind() != std::io::ErrorKind::NotFound {
                    return Err(Error::io(old, e));
                }
            }
        }
        Ok(())
    }

    fn resume(&mut self, c: &Checkpoint) -> Result<()> {
        self.states_file = Some(c.states_file.clone());
        Ok(())
    }
}

//! Kernel replay, a measuring tool (cargo feature `replay`; no default
//! build has it): what share of a step the fibre–fibre kernels take, found
//! by taking them away. A first run of a scene records, for every call of
//! the pair loop (on one thread: [`Replaying`] keeps the candidate loop
//! there), its class, its contact points and the pair's memory after it; a
//! second run of the same scene and flags replays the calls of chosen
//! classes instead of computing them. The replayed calls give the same
//! points and leave the same memories, so the second run is the first bit
//! for bit (its `energy.csv` is the same file), less those kernels' work.
//! `scripts/kernel_share.sh` runs both.
//!
//! `FIBRESIM_REPLAY=record:PATH` writes `PATH.calls` (per call: class, point
//! count, memory), `PATH.points` and `PATH.computations` (the calls before
//! each computation of the pair loop, u64: the first, the start's, is not
//! in a run's timed steps); `FIBRESIM_REPLAY=replay:PATH:CLASSES`
//! replays the classes listed (comma-separated):
//! - `passed`: pairs passed over before the dispatch (apart in every regime);
//! - `kept`: memories kept in their regime that answered (and the rare
//!   answer of such a memory from the dispatch: the signals are the same);
//! - `scan`: calls that ran the end-involved scan (its memory did not
//!   answer, or there was none);
//! - `dispatch`: every other call (side–side, remembered answers that took
//!   the dispatch, capsules apart).

use super::blocks::PairKernel;
use super::fibre_fibre::PairMemory;
use super::{contacts_remembering, Collider, ContactPoint, KernelCounters};
use glam::DVec3;
use std::cell::RefCell;
use std::io::Write;

/// A call's class (see the module doc).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Class {
    /// Passed over before the dispatch.
    Passed = 0,
    /// A memory kept in its regime answered.
    Kept = 1,
    /// Any other call.
    Dispatch = 2,
    /// The end-involved scan ran.
    Scan = 3,
}

const CLASSES: [(&str, Class); 4] = [
    ("passed", Class::Passed),
    ("kept", Class::Kept),
    ("dispatch", Class::Dispatch),
    ("scan", Class::Scan),
];

/// Bytes of a call's record: class, point count, the memory's raw fields.
const CALL_BYTES: usize = 8;
/// f64s of a contact point's record.
const POINT_F64S: usize = 11;

enum Mode {
    Off,
    Record {
        calls: std::io::BufWriter<std::fs::File>,
        points: std::io::BufWriter<std::fs::File>,
        computations: std::io::BufWriter<std::fs::File>,
        recorded: u64,
    },
    Replay {
        calls: Vec<u8>,
        points: Vec<ContactPoint>,
        classes: [bool; 4],
        next_call: usize,
        next_point: usize,
    },
}

thread_local! {
    static MODE: RefCell<Option<Mode>> = const { RefCell::new(None) };
}

/// The candidate loop's fibre pairs, recorded or replayed as
/// `FIBRESIM_REPLAY` asks: each call either answered from the recording
/// (its class replayed) or computed by the kernels (and, when recording,
/// recorded with its class).
pub struct Replaying;

impl PairKernel for Replaying {
    const ONE_THREAD: bool = true;

    fn computation(&self) {
        computation();
    }

    #[inline]
    fn contacts(
        &self,
        a: Collider,
        b: Collider,
        out: &mut Vec<ContactPoint>,
        counters: &mut KernelCounters,
        memory: &mut PairMemory,
        motion: f64,
    ) {
        if replayed(out, memory) {
            return;
        }
        let (kept_before, counted) = (memory.in_regime(), *counters);
        contacts_remembering(a, b, out, counters, Some((memory, motion)));
        if recording() {
            record(classify(kept_before, &counted, counters), out, memory);
        }
    }
}

/// Whether this run records or replays (`FIBRESIM_REPLAY` is set).
pub fn active() -> bool {
    with_mode(|mode| !matches!(mode, Mode::Off))
}

/// What a call did, from the memory before it and the counters' change.
pub fn classify(kept_before: bool, before: &KernelCounters, after: &KernelCounters) -> Class {
    if after.passed_over > before.passed_over {
        Class::Passed
    } else if kept_before
        && after.remembered > before.remembered
        && after.end_scans == before.end_scans
    {
        Class::Kept
    } else if after.end_scans > before.end_scans {
        Class::Scan
    } else {
        Class::Dispatch
    }
}

/// A request this tool cannot serve: the message, exit code 2.
fn refuse(what: &str) -> ! {
    let spec = std::env::var("FIBRESIM_REPLAY").unwrap_or_default();
    eprintln!("error: FIBRESIM_REPLAY={spec}: {what}");
    std::process::exit(2)
}

fn open(spec: &str) -> Mode {
    let create = |path: String| {
        std::fs::File::create(&path)
            .map(std::io::BufWriter::new)
            .unwrap_or_else(|e| refuse(&format!("cannot create {path}: {e}")))
    };
    if let Some(path) = spec.strip_prefix("record:") {
        return Mode::Record {
            calls: create(format!("{path}.calls")),
            points: create(format!("{path}.points")),
            computations: create(format!("{path}.computations")),
            recorded: 0,
        };
    }
    let Some(rest) = spec.strip_prefix("replay:") else {
        refuse("expected record:PATH or replay:PATH:CLASSES")
    };
    let Some((path, list)) = rest.rsplit_once(':') else {
        refuse("expected replay:PATH:CLASSES (passed,kept,dispatch,scan)")
    };
    let mut classes = [false; 4];
    for name in list.split(',').filter(|s| !s.is_empty()) {
        match CLASSES.iter().find(|(n, _)| *n == name) {
            Some(&(_, c)) => classes[c as usize] = true,
            None => refuse(&format!(
                "unknown class {name:?} (passed, kept, dispatch, scan)"
            )),
        }
    }
    let read = |path: String| {
        std::fs::read(&path).unwrap_or_else(|e| refuse(&format!("cannot read {path}: {e}")))
    };
    let calls = read(format!("{path}.calls"));
    let raw = read(format!("{path}.points"));
    let points = raw
        .chunks_exact(8 * POINT_F64S)
        .map(|p| {
            let v = |k: usize| f64::from_le_bytes(p[8 * k..8 * k + 8].try_into().expect("8 bytes"));
            ContactPoint {
                point: DVec3::new(v(0), v(1), v(2)),
                normal: DVec3::new(v(3), v(4), v(5)),
                overlap: v(6),
                weight: v(7),
                weight_grad: DVec3::new(v(8), v(9), v(10)),
            }
        })
        .collect();
    Mode::Replay {
        calls,
        points,
        classes,
        next_call: 0,
        next_point: 0,
    }
}

fn with_mode<R>(f: impl FnOnce(&mut Mode) -> R) -> R {
    MODE.with(|m| {
        let mut m = m.borrow_mut();
        let mode = m.get_or_insert_with(|| match std::env::var("FIBRESIM_REPLAY") {
            Ok(spec) => open(&spec),
            Err(_) => Mode::Off,
        });
        f(mode)
    })
}

/// The next call's recorded answer, if its class is replayed: its points
/// appended to `out`, and `memory` set as the call left it.
#[inline]
pub fn replayed(out: &mut Vec<ContactPoint>, memory: &mut PairMemory) -> bool {
    with_mode(|mode| {
        let Mode::Replay {
            calls,
            points,
            classes,
            next_call,
            next_point,
        } = mode
        else {
            return false;
        };
        let Some(c) = calls.get(*next_call * CALL_BYTES..(*next_call + 1) * CALL_BYTES) else {
            refuse("the run asks for more calls than were recorded: replay the recorded scene and flags")
        };
        let count = usize::from(c[1]);
        let replay = classes[usize::from(c[0])];
        if replay {
            let Some(recorded) = points.get(*next_point..*next_point + count) else {
                refuse("the recorded points ran out: a truncated recording?")
            };
            out.extend_from_slice(recorded);
            let raw = |k: usize| u16::from_le_bytes([c[k], c[k + 1]]);
            *memory = PairMemory::from_raw_any([raw(2), raw(4), raw(6)]);
        }
        *next_call += 1;
        *next_point += count;
        replay
    })
}

/// Record a computed call (when recording).
pub fn record(class: Class, points: &[ContactPoint], memory: &PairMemory) {
    with_mode(|mode| {
        if let Mode::Record {
            calls,
            points: out,
            recorded,
            ..
        } = mode
        {
            *recorded += 1;
            let [code, left, cap] = memory.to_raw();
            let count = u8::try_from(points.len()).expect("a pair has a few points");
            let mut c = [class as u8, count, 0, 0, 0, 0, 0, 0];
            c[2..4].copy_from_slice(&code.to_le_bytes());
            c[4..6].copy_from_slice(&left.to_le_bytes());
            c[6..8].copy_from_slice(&cap.to_le_bytes());
            calls
                .write_all(&c)
                .unwrap_or_else(|e| refuse(&e.to_string()));
            for p in points {
                let v = [
                    p.point.x,
                    p.point.y,
                    p.point.z,
                    p.normal.x,
                    p.normal.y,
                    p.normal.z,
                    p.overlap,
                    p.weight,
                    p.weight_grad.x,
                    p.weight_grad.y,
                    p.weight_grad.z,
                ];
                for x in v {
                    out.write_all(&x.to_le_bytes())
                        .unwrap_or_else(|e| refuse(&e.to_string()));
                }
            }
        }
    })
}

/// A computation of the pair loop starts (when recording, noted).
pub fn computation() {
    with_mode(|mode| {
        if let Mode::Record {
            computations,
            recorded,
            ..
        } = mode
        {
            computations
                .write_all(&recorded.to_le_bytes())
                .unwrap_or_else(|e| refuse(&e.to_string()));
        }
    })
}

/// Whether calls are being recorded (the pair loop then classifies them).
#[inline]
pub fn recording() -> bool {
    with_mode(|mode| matches!(mode, Mode::Record { .. }))
}

/// At the end of the run: flush a recording; check that a replay used
/// every recorded call (else it was not the recorded run: exit code 2).
pub fn finish() {
    with_mode(|mode| match mode {
        Mode::Record {
            calls,
            points,
            computations,
            ..
        } => {
            for file in [calls, points, computations] {
                file.flush().unwrap_or_else(|e| refuse(&e.to_string()));
            }
        }
        Mode::Replay {
            calls, next_call, ..
        } if *next_call * CALL_BYTES != calls.len() => refuse(&format!(
            "replayed {} of {} recorded calls: replay the recorded scene and flags (one thread)",
            *next_call,
            calls.len() / CALL_BYTES
        )),
        _ => {}
    })
}

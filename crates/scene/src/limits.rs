//! Machine limits and the memory estimates checked before anything large
//! is allocated.

use crate::{field, SceneError};

/// What a scene must fit in, checked before anything large is allocated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Memory a run may use (bytes). Default: the machine's available
    /// memory (`MemAvailable` of /proc/meminfo; 8 GiB where unknown).
    pub max_memory: f64,
}

impl Limits {
    /// The machine's available memory.
    pub fn machine() -> Self {
        Self { max_memory: mem_available().unwrap_or(8.0 * GIB) }
    }
}

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

fn mem_available() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

/// Bytes a run needs per element, measured (peak resident set of
/// `signorini run` at m = 2e6 and J = 1e6: 228 and 582 bytes per element)
/// with a margin for the schemes that keep more vectors.
const BYTES_PER_BAR_ELEMENT: f64 = 320.0;
const BYTES_PER_BEAM_ELEMENT: f64 = 800.0;
/// What any run needs besides its mesh (plot buffers, the exact solution).
const BYTES_BASE: f64 = 32.0 * 1024.0 * 1024.0;

/// The memory (bytes) a bar (`beam = false`) or beam run on `elements`
/// elements needs, estimated before allocating it.
pub fn memory_estimate(elements: usize, beam: bool) -> f64 {
    BYTES_BASE + elements as f64 * if beam { BYTES_PER_BEAM_ELEMENT } else { BYTES_PER_BAR_ELEMENT }
}

/// The memory (bytes) the multi-contact solve holds for `k > 1` contacts
/// on `unknowns` unknowns: the influence columns `A⁻¹ e_c` (`8 k n`) and
/// the Delassus matrix with its Cholesky storage (`16 k²`); 0 for one
/// contact (its column is in the per-element estimate).
pub fn contact_memory(k: usize, unknowns: usize) -> f64 {
    if k <= 1 {
        return 0.0;
    }
    let k = k as f64;
    8.0 * k * unknowns as f64 + 16.0 * k * k
}

/// Refuses `k` contacts on `unknowns` unknowns whose solve would not fit
/// beside the mesh, naming `name`.
pub(crate) fn contacts_fit(name: &str, k: usize, unknowns: usize, elements: usize, beam: bool, limits: &Limits) -> Result<(), SceneError> {
    let mesh = memory_estimate(elements, beam);
    let solve = contact_memory(k, unknowns);
    if mesh + solve > limits.max_memory {
        let room = (limits.max_memory - mesh).max(0.0);
        let n = unknowns as f64;
        // The largest k with 8 k n + 16 k² <= room.
        let most = ((-8.0 * n + (64.0 * n * n + 64.0 * room).sqrt()) / 32.0).floor().max(0.0);
        return Err(field(
            name,
            format!(
                "{k} contacts on {unknowns} unknowns need about {} for the multi-contact solve (8·k·n bytes of influence columns A⁻¹e_c, 16·k² of the Delassus matrix and its factor) besides {} for the mesh, beyond the cap of {} (the machine's available memory unless --max-memory is given): at most {most:.0} contacts fit at this mesh; allowed: fewer contacts or elements",
                bytes(solve),
                bytes(mesh),
                bytes(limits.max_memory)
            ),
        ));
    }
    Ok(())
}

/// Human-readable bytes.
pub fn bytes(b: f64) -> String {
    match b {
        b if b >= 1e12 => format!("{:.1} TB", b / 1e12),
        b if b >= 1e9 => format!("{:.1} GB", b / 1e9),
        b if b >= 1e6 => format!("{:.1} MB", b / 1e6),
        b if b >= 1e3 => format!("{:.1} kB", b / 1e3),
        b => format!("{b:.0} B"),
    }
}

pub(crate) fn fits(name: &str, elements: usize, beam: bool, limits: &Limits) -> Result<(), SceneError> {
    let need = memory_estimate(elements, beam);
    if need > limits.max_memory {
        let most = ((limits.max_memory - BYTES_BASE) / (need - BYTES_BASE) * elements as f64).max(0.0).floor();
        return Err(field(
            name,
            format!(
                "{elements} elements need about {} of memory, beyond the cap of {} (the machine's available memory unless --max-memory is given): at most {most:.0} elements fit",
                bytes(need),
                bytes(limits.max_memory)
            ),
        ));
    }
    Ok(())
}

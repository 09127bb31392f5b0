//! What the fuzzer expects of today's reader ([`Config`]) and the words
//! and keys its checks look for.

/// Expectations the reader of today does not meet (each one is a bullet of
/// issue 11); a flag set to `true` checks it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Config {
    /// Emit element counts no machine holds (1e9, 2^40, 2^63 - 1,
    /// 2^64 - 1) for the bar and the beam, and require validation to refuse
    /// them, naming `*.elements`, without allocating (§3 "Sizes"). Today bar
    /// validation allocates the nodal values (1e9: 16 GB; 2^40: abort,
    /// "memory allocation failed"; 2^63 - 1: "capacity overflow" panic;
    /// 2^64 - 1 with a free end: m + 1 wraps to 0 dofs, index panic in
    /// `BarProblem::new`) and beam validation accepts them.
    pub huge_sizes: bool,
    /// Require keys that the chosen contact ignores (`beta` with the penalty,
    /// `penalty_stiffness` with the projection) to be refused (§2 "Silently
    /// ignored keys"). Off: accepting them is tolerated.
    pub refuse_ignored_keys: bool,
    /// Require expressions to evaluate in floating point: `"1/2"` = 0.5,
    /// `"-1/2"` = -0.5, `"2^-1"` = 0.5 (§3 "Expressions"). Off: the values of
    /// integer-division expressions are not checked.
    pub float_expressions: bool,
    /// Require every expression error to name its key (not the table `bar`,
    /// as for a value that is non-finite at a node) and to say what is
    /// allowed (not only evalexpr's message, as for a syntax error).
    pub expression_errors: bool,
    /// Require arrays longer than their fixed size (`stops = [a, b, c]`) to
    /// be a parse error. Today the reader keeps the first two and drops the
    /// rest silently.
    pub exact_arrays: bool,
    /// Emit expressions nested or chained 10^4 to 2·10^5 deep (`((…x…))`,
    /// `--…-x`, `x+x+…+x`, `x^x^…^x`, `math::abs(…)`) and require an answer
    /// without a stack overflow. Today evalexpr recurses: about 5·10^4 levels
    /// overflow the CLI's 8 MiB main thread and abort the process (2·10^4 a
    /// test thread's 2 MiB), so this needs a thread with the CLI's stack.
    pub deep_expressions: bool,
}

impl Config {
    /// What the reader meets today: the six gaps above are tolerated.
    pub const TODAY: Config = Config::STRICT;
    /// Every expectation checked.
    pub const STRICT: Config = Config { huge_sizes: true, refuse_ignored_keys: true, float_expressions: true, expression_errors: true, exact_arrays: true, deep_expressions: true };
}

/// Words that state what is allowed in a message without "not allowed: …"
/// (see [`states_allowed`](crate::states_allowed)), taken from the messages of `scene.rs` and of the
/// library errors it forwards: "invalid m = 1: allowed an integer >= 2",
/// "allowed std, lumped, …", "give dt or ratio", "required without a
/// benchmark", "remove it", "needs a massless contact node", "at most 1e9",
/// "not both", "(must be finite and >= 0)", "t_max <= …", "[0, 1/2]", and the
/// example of a valid expression ("e.g. \"0.5 * (1 - x)\"").
pub const ALLOWED_WORDS: [&str; 11] = ["allowed", ">", "<", "[", "give", "required", "remove", "needs", "at most", "not both", "e.g."];

/// Keys of `[output]` (those of `[bar]` and `[beam]` are matched one by one
/// against `SceneFile` where an error is checked).
pub const OUTPUT_KEYS: [&str; 9] = ["every", "snapshots_every", "plots", "impacts", "poincare", "summary", "transient", "period_tol", "energy_warn"];

/// Bar element counts above this are not validated unless
/// [`Config::huge_sizes`] is set: today validation allocates for them.
pub const MAX_VALIDATED_BAR_ELEMENTS: usize = 20_000;

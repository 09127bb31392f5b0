//! `cargo xtask <study>`: every study's flags come from its `Config`
//! (`signorini_studies::options`): one flag per field, `t_end` as
//! `--t-end`, the field's document as the help and its default from
//! `Config::default()`. A switch on by default is `--no-<name>`; numbers
//! may start with `-` (the study states their range); a list flag takes
//! comma-separated values and may be repeated. What was given goes to the
//! study's one reader (`options::read_valid`), the same as Python's.

use crate::{notes, with_progress_bar, Failure};
use clap::{Arg, ArgAction, ArgMatches, Command};
use signorini_studies::options::{self, Input, Kind, Message, Spelling, Study};
use signorini_studies::{beam, beam_statistics, convergence, courant1, long_horizon, lyapunov, obstacles, oscillator, stress, weighted, work_precision, StudyError};

/// A study: its `Config`, the help line, whether it reports progress, and its run.
pub struct Entry {
    name: &'static str,
    command: fn() -> Command,
    run: fn(&ArgMatches) -> Result<(), Failure>,
}

impl Entry {
    /// `cargo xtask <name>`'s command.
    pub fn command(&self) -> Command {
        (self.command)()
    }
    /// Its name as a subcommand (`beam-statistics`).
    pub fn name(&self) -> &'static str {
        self.name
    }
    /// Reads the flags into the study's `Config` and runs it.
    pub fn run(&self, m: &ArgMatches) -> Result<(), Failure> {
        (self.run)(m)
    }
}

/// The subcommand name of study `C`: `beam_statistics` → `beam-statistics`.
fn subcommand<C: Study>() -> &'static str {
    // Leaked once per study at start-up: clap wants a 'static name.
    Box::leak(C::NAME.replace('_', "-").into_boxed_str())
}

/// One flag per field of `C`, its help from the field's document and
/// its default from `C::default()`.
pub fn command<C: Study>(about: &'static str) -> Command {
    let defaults = C::default();
    let doc = C::DOC.split("\n\n").map(|p| Message::new(&p.split_whitespace().collect::<Vec<_>>().join(" ")).render(Spelling::Flag)).collect::<Vec<_>>().join("\n\n");
    let mut cmd = Command::new(subcommand::<C>()).about(about).long_about(doc);
    for f in C::FIELDS {
        let default = defaults.show(f.name);
        let on_by_default = f.kind == Kind::Switch && default.as_deref() == Some("true");
        let long = if on_by_default { format!("no-{}", f.name.replace('_', "-")) } else { f.name.replace('_', "-") };
        let mut help = f.doc(Spelling::Flag);
        match (&default, f.kind) {
            (_, Kind::Switch) => {}
            (Some(d), _) if !d.is_empty() => help.push_str(&format!(" [default: {d}]")),
            (Some(_), k) if k.is_list() => help.push_str(" [default: none]"),
            _ => {}
        }
        let long: &'static str = Box::leak(long.into_boxed_str());
        let mut arg = Arg::new(f.name).long(long).help(help);
        arg = match f.kind {
            Kind::Switch if on_by_default => arg.action(ArgAction::SetFalse),
            Kind::Switch => arg.action(ArgAction::SetTrue),
            k if k.is_list() => arg.action(ArgAction::Append).num_args(1).value_name(value_name(f.name)),
            _ => arg.action(ArgAction::Set).num_args(1).value_name(value_name(f.name)),
        };
        if f.kind.is_numeric() {
            arg = arg.allow_hyphen_values(true);
        }
        cmd = cmd.arg(arg);
    }
    cmd
}

/// `T_END` for `t_end` (clap wants a 'static name: leaked once per flag).
fn value_name(field: &str) -> &'static str {
    Box::leak(field.to_uppercase().into_boxed_str())
}

/// The fields given on the command line, as the study's reader takes them.
fn given<C: Study>(m: &ArgMatches) -> Vec<(String, Input)> {
    let mut out = Vec::new();
    for f in C::FIELDS {
        if m.value_source(f.name) != Some(clap::parser::ValueSource::CommandLine) {
            continue;
        }
        let input = match f.kind {
            Kind::Switch => Input::switch(m.get_flag(f.name)),
            _ => Input::text(&m.get_many::<String>(f.name).map(|v| v.cloned().collect::<Vec<_>>().join(",")).unwrap_or_default()),
        };
        out.push((f.name.to_string(), input));
    }
    out
}

/// The study's `Config` from the command line, validated; an error names the flag.
pub fn config<C: Study>(m: &ArgMatches) -> Result<C, Failure> {
    options::read_valid::<C>(&given::<C>(m)).map_err(Failure::from)
}

macro_rules! entry {
    ($m:ident, $about:literal, $progress:literal) => {
        Entry {
            name: subcommand::<$m::Config>(),
            command: || command::<$m::Config>($about),
            run: |m| {
                let cfg = config::<$m::Config>(m)?;
                let out = if $progress { with_progress_bar(|p| $m::run(&cfg, p)) } else { $m::run(&cfg, &|_, _| {}) }?;
                notes(&out.notes);
                print!("{}", out.report);
                Ok(())
            },
        }
    };
}

/// Every study, in the order `cargo xtask --help` lists them.
pub fn entries() -> Vec<Entry> {
    vec![
        entry!(convergence, "Convergence study: error norms against dx at fixed dx/dt, and their rates.", true),
        entry!(weighted, "Weighted mass redistribution and the hybrid scheme: figure runs, phase shift, energy, rates.", true),
        entry!(beam, "The beam between two stops: the paper's seven scenes, timings, stability limit, self-convergence.", false),
        entry!(obstacles, "The beam between obstacles along its whole length (problem (P)): feasibility, self-convergence in dt and J, energy balance.", false),
        entry!(oscillator, "The impact oscillator scene against its exact period-1 orbits (rates in dt) and its grazing frequency.", false),
        entry!(work_precision, "Work–precision: error reached against wall time per scheme and mass.", false),
        entry!(stress, "Stability stress: long runs, extreme dx/dt, random data; energy drift and blow-ups.", false),
        entry!(courant1, "Courant number one: the lumped central difference at dx/dt = c, node by node against the exact solutions.", false),
        entry!(long_horizon, "The Dirichlet bar over many periods (T = 30): error against time and impact phase for every mass.", true),
        entry!(lyapunov, "The largest Lyapunov exponent (Benettin's twin runs) of the paper's beam scenes, beam-obstacles and the impact oscillator, and the predictability horizon.", true),
        entry!(beam_statistics, "Statistics of the beam scenes over a long window with 95 % batch-means intervals, against dt and J: which converge.", true),
    ]
}

impl From<StudyError> for Failure {
    /// A study's [`StudyError::Config`] is bad input (its fields spelled as
    /// flags); anything else a failure.
    fn from(e: StudyError) -> Self {
        match e {
            StudyError::Config { .. } => Failure::Input(e.render(Spelling::Flag)),
            other => Failure::Failed(other.to_string()),
        }
    }
}

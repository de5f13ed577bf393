//! Which time windows a solve uses (METHOD §7), chosen from what the run is for when nobody
//! asked for a length, and the reason, which the run's report prints.
//!
//! The choice follows measurements on the built-in scenes (the guide, docs/src/iterations.md, gives the figures):
//! for one cold solve of a scene with contact, one-step windows reach a given η in less time than
//! the whole interval, for an error of the same size against the converged solution; without
//! contact (`bar`, `bar-bimaterial`) the whole interval reaches the default η < 1e-3 in a few
//! tens of iterations, faster than the windows. The explorer's slider restarts from a converged
//! neighbour over the whole interval, where a few iterations suffice, and streams each iterate
//! of the whole interval into the view. A study of a scene with contact (`lopin study`,
//! `lopin sweep`) runs one-step windows, each started from the nearest solved configuration's
//! converged steps: the whole interval gains more iterations per warm start, but each of its
//! iterations marches every step, and the error a moved impact leaves crosses the interval at
//! about a third of a step per iteration.

use std::fmt;

/// What a solve is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Task {
    /// One cold solve (`lopin run`, `compare`, `estimate`).
    #[default]
    Single,
    /// A warm-started study: each value restarts from a converged one (`lopin study`, `lopin
    /// sweep`).
    Study,
    /// The explorer: a cold solve, then warm re-solves after each slider move.
    Interactive,
}

/// What the user asked for: on the command line (`--window`), in the scene's `[solver]` table
/// (`window = 4`, `window = "whole"`) or in the explorer. In a scene or a record it is a number
/// of steps or one of the words `whole` and `auto`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WindowRequest {
    /// Nothing: the scene's `solver.window` if it has one, else the choice for the task.
    #[default]
    Auto,
    /// The whole interval (the non-incremental method).
    Whole,
    /// Windows of this many steps (≥ 1).
    Steps(usize),
}

/// How a [`WindowRequest`] is written in a scene or a record, for the scene's schema.
#[cfg(feature = "schema")]
#[derive(schemars::JsonSchema)]
#[serde(untagged)]
pub enum WindowValue {
    /// A number of steps (≥ 1).
    Steps(usize),
    /// `whole` or `auto`.
    Word(String),
}

impl serde::Serialize for WindowRequest {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            Self::Steps(n) => serializer.serialize_u64(*n as u64),
            Self::Whole => serializer.serialize_str("whole"),
            Self::Auto => serializer.serialize_str("auto"),
        }
    }
}

impl<'de> serde::Deserialize<'de> for WindowRequest {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(RequestVisitor)
    }
}

/// Reads a number of steps or a word.
struct RequestVisitor;

impl serde::de::Visitor<'_> for RequestVisitor {
    type Value = WindowRequest;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a number of steps >= 1, `whole` or `auto`")
    }

    fn visit_u64<E: serde::de::Error>(self, n: u64) -> Result<WindowRequest, E> {
        // 0 reads, and the scene's validation refuses it under the field's name
        usize::try_from(n)
            .map(WindowRequest::Steps)
            .map_err(|_| E::custom(format!("{n} steps is too many")))
    }

    fn visit_i64<E: serde::de::Error>(self, n: i64) -> Result<WindowRequest, E> {
        u64::try_from(n)
            .map_err(|_| E::custom(format!("expected a number of steps >= 1, got {n}")))
            .and_then(|n| self.visit_u64(n))
    }

    fn visit_str<E: serde::de::Error>(self, word: &str) -> Result<WindowRequest, E> {
        WindowRequest::parse(word).map_err(E::custom)
    }
}

impl WindowRequest {
    /// The window length this request fixes by itself (None: the whole interval, or, for
    /// `auto`, what [`choose`] picks).
    pub fn steps(self) -> Option<usize> {
        match self {
            Self::Steps(n) => Some(n),
            Self::Whole | Self::Auto => None,
        }
    }

    /// Parses `auto`, `whole` or a number of steps ≥ 1; the error says what is accepted.
    pub fn parse(text: &str) -> Result<Self, String> {
        match text {
            "auto" => Ok(Self::Auto),
            "whole" => Ok(Self::Whole),
            _ => match text.parse::<usize>() {
                Ok(0) => Err("must be at least 1 step".into()),
                Ok(n) => Ok(Self::Steps(n)),
                Err(_) => Err(format!(
                    "expected a number of steps >= 1, `whole` or `auto`, got `{text}`"
                )),
            },
        }
    }
}

/// The windows chosen and why.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct WindowChoice {
    /// Window length in steps (None: the whole interval).
    pub window: Option<usize>,
    /// Why, in words.
    pub reason: String,
}

impl fmt::Display for WindowChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.window {
            None => write!(f, "whole interval ({})", self.reason),
            Some(n) => write!(
                f,
                "{n}-step window{} ({})",
                if n == 1 { "" } else { "s" },
                self.reason
            ),
        }
    }
}

/// The windows of a solve: the request, else the scene's `solver.window`, else the task's (one
/// cold solve or a study: one-step windows if the scene has contact, else the whole interval;
/// the explorer: the whole interval). `auto`, in the request or the scene, is no request.
pub fn choose(
    task: Task,
    request: Option<WindowRequest>,
    scene_window: Option<WindowRequest>,
    contact: bool,
) -> WindowChoice {
    let request = request.unwrap_or_default();
    let scene_window = scene_window.unwrap_or_default();
    let (window, reason) = match (request, scene_window, task) {
        (WindowRequest::Steps(n), _, _) => (Some(n), "asked for".to_string()),
        (WindowRequest::Whole, _, _) => (None, "asked for".to_string()),
        (WindowRequest::Auto, WindowRequest::Steps(n), _) => {
            (Some(n), "the scene's solver.window".to_string())
        }
        (WindowRequest::Auto, WindowRequest::Whole, _) => {
            (None, "the scene's solver.window".to_string())
        }
        (WindowRequest::Auto, WindowRequest::Auto, Task::Single) if !contact => (
            None,
            "auto: one cold solve without contact, which the whole interval converges in few \
             iterations; --window 1 for the incremental method"
                .to_string(),
        ),
        (WindowRequest::Auto, WindowRequest::Auto, Task::Single) => (
            Some(1),
            "auto: one cold solve with contact, where one-step windows reach the tolerance \
             fastest; \
             --window whole for the whole interval"
                .to_string(),
        ),
        (WindowRequest::Auto, WindowRequest::Auto, Task::Study) if !contact => (
            None,
            "auto: a warm-started study without contact, each value restarting the whole \
             interval from a converged one"
                .to_string(),
        ),
        (WindowRequest::Auto, WindowRequest::Auto, Task::Study) => (
            Some(1),
            "auto: a warm-started study with contact, where one-step windows started from the \
             nearest solved configuration reach the tolerance fastest; --window whole for the \
             whole interval"
                .to_string(),
        ),
        (WindowRequest::Auto, WindowRequest::Auto, Task::Interactive) if !contact => (
            None,
            "auto: the explorer re-solves the whole interval warm after each change, a scene \
             without contact converging in few iterations"
                .to_string(),
        ),
        (WindowRequest::Auto, WindowRequest::Auto, Task::Interactive) => (
            Some(1),
            "auto: the explorer re-solves a scene with contact warm after each change on \
             one-step windows, which reach the tolerance fastest from the nearest solved \
             configuration"
                .to_string(),
        ),
    };
    WindowChoice { window, reason }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_request_wins_then_the_scene_then_the_task() {
        let c = choose(
            Task::Study,
            Some(WindowRequest::Steps(4)),
            Some(WindowRequest::Steps(2)),
            true,
        );
        assert_eq!(c.window, Some(4));
        let c = choose(
            Task::Single,
            Some(WindowRequest::Whole),
            Some(WindowRequest::Steps(2)),
            true,
        );
        assert_eq!(c.window, None);
        let c = choose(Task::Single, None, Some(WindowRequest::Steps(2)), true);
        assert_eq!(
            (c.window, c.reason.as_str()),
            (Some(2), "the scene's solver.window")
        );
        let c = choose(Task::Single, None, None, true);
        assert_eq!(c.window, Some(1));
        let c = choose(Task::Single, None, None, false);
        assert_eq!(c.window, None);
        let explorer = choose(Task::Interactive, None, None, true);
        assert_eq!(explorer.window, Some(1));
        assert!(explorer.reason.contains("one-step windows"), "{explorer}");
        assert_eq!(choose(Task::Interactive, None, None, false).window, None);
        let study = choose(Task::Study, None, None, true);
        assert_eq!(study.window, Some(1));
        assert!(study.reason.contains("study with contact"), "{study}");
        assert_eq!(choose(Task::Study, None, None, false).window, None);
        let shown = choose(Task::Single, None, None, true).to_string();
        assert!(
            shown.starts_with("1-step window (auto: one cold solve with contact"),
            "{shown}"
        );
    }

    #[test]
    fn the_scene_can_ask_for_the_whole_interval_and_auto_is_no_request() {
        let whole = Some(WindowRequest::Whole);
        let c = choose(Task::Single, None, whole, true);
        assert_eq!(
            (c.window, c.reason.as_str()),
            (None, "the scene's solver.window")
        );
        let auto = Some(WindowRequest::Auto);
        assert_eq!(choose(Task::Single, auto, whole, true).window, None);
        assert_eq!(choose(Task::Study, None, auto, true).window, Some(1));
        assert_eq!(
            choose(Task::Study, Some(WindowRequest::Steps(3)), whole, true).window,
            Some(3)
        );
    }

    #[test]
    fn requests_read_and_write_as_a_number_or_a_word() {
        #[derive(serde::Serialize, serde::Deserialize, Debug, PartialEq)]
        struct T {
            window: WindowRequest,
        }
        for (text, request) in [
            ("window = 4", WindowRequest::Steps(4)),
            ("window = \"whole\"", WindowRequest::Whole),
            ("window = \"auto\"", WindowRequest::Auto),
        ] {
            let read: T = toml::from_str(text).expect(text);
            assert_eq!(read.window, request);
            assert_eq!(toml::to_string(&read).expect("writes").trim(), text);
        }
        let e = toml::from_str::<T>("window = \"half\"")
            .expect_err("a word other than whole and auto")
            .to_string();
        assert!(e.contains("`whole` or `auto`, got `half`"), "{e}");
    }

    #[test]
    fn requests_parse_and_bad_ones_say_what_is_accepted() {
        assert_eq!(WindowRequest::parse("auto"), Ok(WindowRequest::Auto));
        assert_eq!(WindowRequest::parse("whole"), Ok(WindowRequest::Whole));
        assert_eq!(WindowRequest::parse("5"), Ok(WindowRequest::Steps(5)));
        assert_eq!(
            WindowRequest::parse("0"),
            Err("must be at least 1 step".into())
        );
        for bad in ["-1", "half", ""] {
            assert!(
                matches!(WindowRequest::parse(bad), Err(e) if e.contains("`whole` or `auto`")),
                "{bad}"
            );
        }
    }
}

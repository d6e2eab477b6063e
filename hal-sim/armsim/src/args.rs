//! What the host tools' command lines share: how a bad argument is reported
//! (one line, exit code 2, so scripts can tell it from a failed run) and the
//! `X,Y` values they take.

use std::process::ExitCode;

use clap::Parser;

/// When this environment variable is set, `touch-arm-sim` and
/// `touch-arm-live` exit after parsing their arguments (0, or 2 with the
/// error): how the documented commands are checked without running them.
pub const CHECK_ARGS: &str = "TOUCH_ARM_CHECK_ARGS";

/// Parses the process arguments. `Err` carries the exit code to return at
/// once: 0 after `--help`/`--version` (printed), 2 after a bad argument
/// (one line on stderr, `prog: <what is wrong>`).
pub fn parse<P: Parser>(prog: &str) -> Result<P, ExitCode> {
    match P::try_parse() {
        Ok(p) => Ok(p),
        Err(e) if e.use_stderr() => {
            // clap's message is its first paragraph (a list of missing
            // arguments continues on indented lines); usage and tips follow
            // after a blank line, and `--help` has the full text.
            let text = e.render().to_string();
            let message: Vec<&str> = text.lines().take_while(|l| !l.trim().is_empty()).map(str::trim).collect();
            eprintln!("{prog}: {}", message.join(" ").trim_start_matches("error: "));
            Err(ExitCode::from(2))
        }
        Err(e) => {
            let _ = e.print();
            Err(ExitCode::SUCCESS)
        }
    }
}

/// Whether a tool's run kept [`parse`]'s convention for a bad argument:
/// exit code 2, nothing on stdout, one line on stderr starting with the
/// program's name and containing `needle`. `Err` says what was broken; the
/// tests of every tool that parses with [`parse`] assert with it.
pub fn bad_argument_report(name: &str, out: &std::process::Output, needle: &str) -> Result<(), String> {
    let err = String::from_utf8_lossy(&out.stderr);
    if out.status.code() != Some(2) {
        return Err(format!("{name}: exit {:?}, not 2: {err}", out.status.code()));
    }
    if !out.stdout.is_empty() {
        return Err(format!("{name} printed {:?}", String::from_utf8_lossy(&out.stdout)));
    }
    if err.trim_end().lines().count() != 1 {
        return Err(format!("{name}: not one line: {err}"));
    }
    if !(err.starts_with(&format!("{name}: ")) && err.contains(needle)) {
        return Err(format!("{name}: {err:?} lacks {needle:?}"));
    }
    Ok(())
}

/// Two finite numbers "X,Y".
pub fn parse_pair(s: &str) -> Result<(f64, f64), String> {
    let (a, b) = s.split_once(',').ok_or_else(|| format!("expected X,Y, got {s:?}"))?;
    let p = |v: &str| v.trim().parse::<f64>().map_err(|_| format!("not a number: {v:?}"));
    let (a, b) = (p(a)?, p(b)?);
    if !(a.is_finite() && b.is_finite()) {
        return Err("coordinates must be finite".into());
    }
    Ok((a, b))
}

/// A point "X,Y,Z" of finite numbers.
pub fn parse_triple(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').collect();
    let [a, b, c] = parts[..] else {
        return Err(format!("expected X,Y,Z, got {s:?}"));
    };
    let p = |v: &str| v.trim().parse::<f64>().map_err(|_| format!("not a number: {v:?}"));
    let v = [p(a)?, p(b)?, p(c)?];
    if !v.iter().all(|x| x.is_finite()) {
        return Err("coordinates must be finite".into());
    }
    Ok(v)
}

/// A raw panel reading "X,Y": two 10-bit ADC values.
pub fn parse_raw(s: &str) -> Result<(u16, u16), String> {
    let (a, b) = s.split_once(',').ok_or_else(|| format!("expected X,Y, got {s:?}"))?;
    let p = |v: &str| match v.trim().parse::<u16>() {
        Ok(n) if n <= 1023 => Ok(n),
        _ => Err(format!("raw ADC value must be an integer 0..=1023, got {v:?}")),
    };
    Ok((p(a)?, p(b)?))
}

//! What an Eclipse deck says about running it, as single-phase water in
//! METRIC units: its schedule (WCONPROD, WCONINJE, TSTEP, DATES after START)
//! and its initial state (EQUIL). Every translation is said in the notes.

use super::eclipse::{each_record, is_keyword, number, record, Record, Tok, Tokens};
use crate::error::{Error, Result};
use crate::reservoir::deck::{Control, Period};
use chrono::{Datelike, NaiveDate};
use std::path::Path;

/// Standard barrels per cubic metre, and bar per psi (FIELD to METRIC).
const STB: f64 = 0.158_987_294_928;
const PSI: f64 = 0.068_947_572_931_783_1;
/// Bar per atmosphere (LAB pressures).
const ATM: f64 = 1.01325;

/// The deck's unit system (FIELD, METRIC, LAB) as read from its RUNSPEC
/// keywords; GRIDUNIT, which is only about the grid's lengths, is not it.
fn unit_system(ts: &Tokens) -> &'static str {
    ts.toks
        .iter()
        .filter(|t| is_keyword(t))
        .find_map(|t| match t.text.as_str() {
            "FIELD" => Some("FIELD"),
            "LAB" => Some("LAB"),
            "METRIC" => Some("METRIC"),
            _ => None,
        })
        .unwrap_or("METRIC")
}

/// The reading of one schedule: the deck's tokens and units, the wells of
/// the mesh, and what was said.
struct Reader<'a> {
    ts: Tokens,
    /// sm3 per rate unit, bar per pressure unit.
    rate: f64,
    press: f64,
    names: &'a [String],
    notes: Vec<String>,
}

impl Reader<'_> {
    fn value(&self, r: &Record, n: usize) -> Result<Option<f64>> {
        match r.get(n).cloned().flatten() {
            None => Ok(None),
            Some(t) => number(&self.ts, &Some(t.clone()), &t, "a number").map(Some),
        }
    }

    fn word(r: &Record, n: usize, default: &str) -> String {
        r.get(n)
            .cloned()
            .flatten()
            .map_or(default.to_string(), |t| t.text.trim().to_uppercase())
    }

    /// A WCONPROD or WCONINJE record as a water control, translations said.
    fn control(&mut self, producer: bool, rec: &Record) -> Result<Control> {
        let pattern = Self::word(rec, 0, "");
        if producer {
            let bhp = self.value(rec, 8)?.map_or(1.01325, |p| p * self.press);
            let mode = Self::word(rec, 2, "");
            let item = ["ORAT", "WRAT", "GRAT", "LRAT", "RESV"]
                .iter()
                .position(|m| *m == mode);
            return Ok(match (Self::word(rec, 1, "OPEN").as_str(), item) {
                ("SHUT" | "STOP", _) => Control::Shut,
                (_, Some(2)) | (_, None) => {
                    self.notes.push(format!(
                        "{pattern}: {mode} control written as BHP {bhp:.4} bar"
                    ));
                    Control::ProduceAtBhp(bhp)
                }
                (_, Some(i)) => Control::Produce {
                    rate: self.value(rec, 3 + i)?.unwrap_or(0.0) * self.rate,
                    min_bhp: bhp,
                },
            });
        }
        let max_bhp = self.value(rec, 6)?.map_or(1000.0, |p| p * self.press);
        let kind = Self::word(rec, 1, "WATER");
        if kind != "WATER" {
            self.notes
                .push(format!("{pattern}: injects water, not {kind}"));
        }
        let (status, mode) = (Self::word(rec, 2, "OPEN"), Self::word(rec, 3, "RATE"));
        Ok(match (status.as_str(), mode.as_str()) {
            ("SHUT" | "STOP", _) => Control::Shut,
            (_, "RATE") => Control::Inject {
                rate: self.value(rec, 4)?.unwrap_or(0.0) * self.rate,
                max_bhp,
            },
            (_, mode) => {
                self.notes.push(format!(
                    "{pattern}: {mode} control written as a rate of 1e5 sm3/day up to {max_bhp:.4} bar"
                ));
                Control::Inject { rate: 1e5, max_bhp }
            }
        })
    }

    /// The mesh's wells a record's name or pattern ('P*') names; none is said.
    fn matched(&mut self, keyword: &str, rec: &Record) -> Vec<String> {
        let pattern = Self::word(rec, 0, "");
        let matched: Vec<String> = self
            .names
            .iter()
            .filter(|n| match pattern.strip_suffix('*') {
                Some(prefix) => n.starts_with(prefix),
                None => **n == pattern,
            })
            .cloned()
            .collect();
        if matched.is_empty() {
            self.notes
                .push(format!("{keyword} '{pattern}' matches no well of the mesh"));
        }
        matched
    }

    /// A date record (START, DATES: day, month, year, optional time) in
    /// days since the common era.
    fn date(&self, kw: &Tok, rec: &Record) -> Result<f64> {
        let bad = || {
            let text: Vec<String> = rec.iter().flatten().map(|t| t.text.clone()).collect();
            self.ts.error(
                kw,
                format!(
                    "{}: '{}' is not a date (day 'MON' year)",
                    kw.text,
                    text.join(" ")
                ),
            )
        };
        let month = Self::word(rec, 1, "");
        let months = [
            "JAN", "FEB", "MAR", "APR", "MAY", "JUN", "JUL", "AUG", "SEP", "OCT", "NOV", "DEC",
        ];
        let m = match months.iter().position(|x| *x == month) {
            Some(m) => m as u32 + 1,
            None if month == "JLY" => 7,
            None => return Err(bad()),
        };
        let day: u32 = number(&self.ts, &rec.first().cloned().flatten(), kw, "a day")?;
        let year: i32 = number(&self.ts, &rec.get(2).cloned().flatten(), kw, "a year")?;
        let date = NaiveDate::from_ymd_opt(year, m, day).ok_or_else(bad)?;
        let mut days = date.num_days_from_ce() as f64;
        if let Some(t) = rec.get(3).cloned().flatten() {
            let hms: Vec<f64> = t
                .text
                .split(':')
                .map(|x| x.parse().unwrap_or(f64::NAN))
                .collect();
            let time = hms
                .iter()
                .zip([24.0, 1440.0, 86400.0])
                .map(|(v, d)| v / d)
                .sum::<f64>();
            if !(hms.len() <= 3 && (0.0..1.0).contains(&time)) {
                return Err(bad());
            }
            days += time;
        }
        Ok(days)
    }
}

/// A deck's schedule as single-phase water controls in METRIC units: its
/// periods, each the controls that change (WCONPROD, WCONINJE; names with a
/// trailing '*' match every well of `names` they start) and then its report
/// steps (TSTEP, or DATES counted from START). Reading stops at END.
pub fn read_schedule(path: &Path, names: &[String]) -> Result<(Vec<Period>, Vec<String>)> {
    let ts = Tokens::read(path, true)?;
    let (rate, press) = match unit_system(&ts) {
        "FIELD" => (STB, PSI),
        "LAB" => {
            return Err(Error::Usage(format!(
                "{}: LAB units in a schedule are not read",
                path.display()
            )))
        }
        _ => (1.0, 1.0),
    };
    let mut r = Reader {
        ts,
        rate,
        press,
        names,
        notes: vec![],
    };
    let (mut periods, mut pending): (Vec<Period>, Vec<(String, Control)>) = (vec![], vec![]);
    let (mut start, mut elapsed) = (None, 0.0);
    let mut k = 0;
    while k < r.ts.toks.len() {
        let kw = r.ts.toks[k].clone();
        k += 1;
        if !is_keyword(&kw) {
            continue;
        }
        let mut steps = vec![];
        match kw.text.as_str() {
            "WCONPROD" | "WCONINJE" => {
                let mut records = vec![];
                k = each_record(&r.ts, k, &kw, |rec| {
                    records.push(rec);
                    Ok(())
                })?;
                for rec in records {
                    let control = r.control(kw.text == "WCONPROD", &rec)?;
                    let matched = r.matched(&kw.text, &rec);
                    pending.retain(|(n, _)| !matched.contains(n));
                    pending.extend(matched.into_iter().map(|n| (n, control)));
                }
            }
            "START" => {
                let (rec, next) = record(&r.ts, k, &kw)?;
                k = next;
                start = Some(r.date(&kw, &rec)?);
            }
            "TSTEP" => {
                let (rec, next) = record(&r.ts, k, &kw)?;
                k = next;
                for n in 0..rec.len() {
                    let d = r.value(&rec, n)?.unwrap_or(0.0);
                    if !(d > 0.0 && d.is_finite()) {
                        return Err(r
                            .ts
                            .error(&kw, format!("TSTEP: step {} is {d} days", n + 1)));
                    }
                    steps.push(d);
                }
            }
            "DATES" => {
                let Some(origin) = start else {
                    return Err(r
                        .ts
                        .error(&kw, "DATES without START: the dates have no origin".into()));
                };
                let mut records = vec![];
                k = each_record(&r.ts, k, &kw, |rec| {
                    records.push(rec);
                    Ok(())
                })?;
                let mut at = elapsed;
                for rec in records {
                    let day = r.date(&kw, &rec)? - origin;
                    if day <= at {
                        let text: Vec<String> =
                            rec.iter().flatten().map(|t| t.text.clone()).collect();
                        return Err(r.ts.error(
                            &kw,
                            format!(
                                "DATES {}: day {day} is not after day {at} of the schedule",
                                text.join(" ")
                            ),
                        ));
                    }
                    steps.push(day - at);
                    at = day;
                }
            }
            "END" => break,
            _ => {}
        }
        if !steps.is_empty() {
            elapsed += steps.iter().sum::<f64>();
            periods.push(Period {
                controls: std::mem::take(&mut pending),
                steps,
            });
        }
    }
    Ok((periods, r.notes))
}

/// A deck's EQUIL: the datum depth (m) and the pressure there (bar) in its
/// first equilibration region, with the record as the deck wrote it; None
/// when the deck has no EQUIL.
pub fn read_equil(path: &Path) -> Result<Option<(f64, f64, String)>> {
    let ts = Tokens::read(path, true)?;
    let (length, press, unit) = match unit_system(&ts) {
        "FIELD" => (0.3048, PSI, "ft, psia"),
        "LAB" => (0.01, ATM, "cm, atm"),
        _ => (1.0, 1.0, "m, bar"),
    };
    let Some(k) = ts
        .toks
        .iter()
        .position(|t| is_keyword(t) && t.text == "EQUIL")
    else {
        return Ok(None);
    };
    let kw = ts.toks[k].clone();
    let (rec, _) = record(&ts, k + 1, &kw)?;
    let datum: f64 = number(
        &ts,
        &rec.first().cloned().flatten(),
        &kw,
        "EQUIL's datum depth",
    )?;
    let p: f64 = number(
        &ts,
        &rec.get(1).cloned().flatten(),
        &kw,
        "EQUIL's datum pressure",
    )?;
    if !(datum.is_finite() && p > 0.0 && p.is_finite()) {
        return Err(ts.error(&kw, format!("EQUIL: datum {datum}, pressure {p}")));
    }
    let said = format!("EQUIL of {}: {datum} {p} ({unit})", path.display());
    Ok(Some((datum * length, p * press, said)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn write(name: &str, text: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("orthomesh-schedule-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }
    #[test]
    fn schedules_become_water_controls_in_metric_units() {
        let p = write(
            "SCHED.DATA",
            "FIELD\nSTART\n 1 'JAN' 2030 /\nSCHEDULE\nWCONPROD\n 'P*' 'OPEN' 'ORAT' 1500 4* 1000 /\n 'X' 'SHUT' 'ORAT' 1 /\n/\n\
             WCONINJE\n 'I' 'WATER' 'OPEN' 'RATE' 5000 1* 4000 /\n/\nTSTEP\n 2*10 /\n\
             WCONPROD\n 'P1' 'OPEN' 'BHP' 5* 500 /\n/\nTSTEP\n 5 /\nDATES\n 1 'FEB' 2030 /\n 1 'FEB' 2030 12:00:00 /\n/\nTSTEP\n 7 /\nEND\nTSTEP\n 9 /\n",
        );
        let names: Vec<String> = ["P1", "P2", "I"].iter().map(|s| s.to_string()).collect();
        let (periods, notes) = read_schedule(&p, &names).unwrap();
        assert_eq!(periods.len(), 4);
        assert_eq!(periods[0].steps, vec![10.0, 10.0]);
        let produce = Control::Produce {
            rate: 1500.0 * STB,
            min_bhp: 1000.0 * PSI,
        };
        assert_eq!(periods[0].controls[0], ("P1".to_string(), produce));
        assert_eq!(periods[0].controls[1], ("P2".to_string(), produce));
        let inject = Control::Inject {
            rate: 5000.0 * STB,
            max_bhp: 4000.0 * PSI,
        };
        assert_eq!(periods[0].controls[2], ("I".to_string(), inject));
        assert_eq!(
            periods[1].controls,
            vec![("P1".to_string(), Control::ProduceAtBhp(500.0 * PSI))]
        );
        assert!(
            notes.iter().any(|n| n.contains("'X' matches no well")),
            "{notes:?}"
        );
        // DATES count from START, after the 25 days of TSTEP; END ends it.
        assert_eq!(periods[2].steps, vec![6.0, 0.5]);
        assert_eq!(periods[3].steps, vec![7.0]);
    }

    #[test]
    fn dates_need_an_origin_and_must_move_on() {
        let bad = |name: &str, text: &str| {
            read_schedule(&write(name, text), &[])
                .unwrap_err()
                .to_string()
        };
        let e = bad("NOSTART.DATA", "DATES\n 1 'JAN' 2030 /\n/\n");
        assert!(
            e.contains("DATES without START") && e.contains(":1:"),
            "{e}"
        );
        let e = bad(
            "BACK.DATA",
            "START\n 1 'JAN' 2030 /\nTSTEP\n 40 /\nDATES\n 1 'FEB' 2030 /\n/\n",
        );
        assert!(e.contains("day 31 is not after day 40"), "{e}");
        let e = bad("MONTH.DATA", "START\n 1 'JUNO' 2030 /\n");
        assert!(e.contains("'1 JUNO 2030' is not a date"), "{e}");
        let e = bad("FEB30.DATA", "START\n 30 'FEB' 2030 /\n");
        assert!(e.contains("is not a date"), "{e}");
        let e = bad("ZERO.DATA", "TSTEP\n 10 0 /\n");
        assert!(e.contains("TSTEP: step 2 is 0 days"), "{e}");
    }

    #[test]
    fn equil_gives_datum_and_pressure_in_metric_units() {
        let p = write("EQ.DATA", "FIELD\nSOLUTION\nEQUIL\n 9035 3600 9950 0 /\n");
        let (datum, pressure, said) = read_equil(&p).unwrap().unwrap();
        assert!((datum - 9035.0 * 0.3048).abs() < 1e-9);
        assert!((pressure - 3600.0 * PSI).abs() < 1e-9);
        assert!(said.contains("9035 3600 (ft, psia)"), "{said}");
        assert!(read_equil(&write("NONE.DATA", "METRIC\n"))
            .unwrap()
            .is_none());
        let e = read_equil(&write("NEG.DATA", "EQUIL\n 100 -5 /\n")).unwrap_err();
        assert!(
            e.to_string().contains("EQUIL: datum 100, pressure -5"),
            "{e}"
        );
    }
}

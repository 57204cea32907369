//! `flipcard sim --scene ID --prompt P [--variant SEED]`: a prompt as one
//! attempt asks it (issue 24 §2), for instructors and tests: a varied
//! prompt's numbers drawn from SEED, its question in every language with
//! them filled in, and the answer the variant's run gives (the measured
//! number, or the choice whose `when` holds). Exit 1 when the run does
//! not decide the answer.

use std::process::ExitCode;

use anyhow::{anyhow, bail};
use serde_json::json;

use crate::cmd::args::{SimArgs, SimFormat};
use crate::deck::{Answer, Deck};
use crate::predict::audit::variant_run;
use crate::predict::variant::{self, MAX_SEED, Undecided};
use crate::text::num::Num;
use crate::text::safe::one_line;

pub fn run(args: &SimArgs, decks: &[Deck], scene: &str, id: &str) -> anyhow::Result<ExitCode> {
    let deck = decks
        .iter()
        .find(|d| d.system(scene).is_some() || d.scene(scene).is_some())
        .ok_or_else(|| anyhow!("no scene {scene:?}"))?;
    let Some(prompt) = deck.prompts.iter().find(|p| p.id == id && p.scene == scene) else {
        let on: Vec<&str> = deck
            .prompts
            .iter()
            .filter(|p| p.scene == scene)
            .map(|p| p.id.as_str())
            .collect();
        bail!(
            "no prompt {:?} on scene {scene} (its prompts: {})",
            one_line(id),
            if on.is_empty() {
                "none".to_string()
            } else {
                on.join(", ")
            }
        );
    };
    let chosen = match (args.variant, prompt.vary.is_empty()) {
        (Some(_), true) => {
            bail!("--variant: prompt {id} does not vary (it has no `vary`); leave out --variant")
        }
        (None, false) => {
            bail!("prompt {id} varies: give --variant SEED (0 to {MAX_SEED}) to choose its numbers")
        }
        (Some(seed), false) if seed > MAX_SEED => {
            bail!("--variant {seed}: a seed is at most {MAX_SEED} (2^53 − 1)")
        }
        (Some(seed), false) => Some(variant::draw(prompt, seed)),
        (None, true) => None,
    };
    let resolved = variant::resolve(deck, prompt, chosen.as_ref())
        .ok_or_else(|| anyhow!("scene {scene} is not in deck {}", deck.id))?;
    let run = variant_run(deck, &resolved).map_err(|e| anyhow!("scene {scene}: {e}"))?;
    let decided = variant::decided(&resolved.prompt, &run.measured);
    let p = &resolved.prompt;
    let languages: Vec<String> = deck.languages.iter().map(|l| l.to_string()).collect();
    let question = |lang: &str| one_line(&crate::text::render(p.question.get(lang))).into_owned();
    let answer = match (&decided, &p.answer) {
        (Ok(d), Answer::Number { measure, unit, .. }) => {
            let Answer::Number { expected, .. } = &d.answer else {
                unreachable!("decided keeps the kind")
            };
            let v = expected.unwrap_or(f64::NAN);
            Ok((
                format!("{measure} = {} {unit}", Num(v))
                    .trim_end()
                    .to_string(),
                json!({ "measure": measure.to_string(), "value": v, "unit": unit }),
            ))
        }
        (Ok(d), Answer::Choice { choices, .. }) => {
            let Answer::Choice { expected, .. } = &d.answer else {
                unreachable!("decided keeps the kind")
            };
            let right = expected.clone().unwrap_or_default();
            let holding: Vec<&str> = choices
                .iter()
                .filter(|c| c.when.holds_on(|m| run.measured.get(m)).unwrap_or(false))
                .map(|c| c.id.as_str())
                .collect();
            let label = choices
                .iter()
                .find(|c| c.id == right)
                .map(|c| one_line(&crate::text::render(c.label.get(&languages[0]))).into_owned())
                .unwrap_or_default();
            Ok((
                format!("choice {right} ({label})"),
                json!({ "choice": right, "holds": holding }),
            ))
        }
        (Ok(_), Answer::Formula(key)) => Ok((
            format!("formula {}", one_line(&key.expected)),
            json!({ "formula": key.expected }),
        )),
        (Err(u), _) => Err(match u {
            Undecided::NotMeasured => "the run cannot make the prompt's measure".to_string(),
            Undecided::NoChoice => "no choice's `when` holds in this run".to_string(),
            Undecided::Several(ids) => format!("choices {} all hold", ids.join(", ")),
        }),
    };
    let values: serde_json::Map<String, serde_json::Value> = resolved
        .variant
        .as_ref()
        .map(|v| {
            v.values
                .iter()
                .map(|(n, x)| (n.clone(), json!(x)))
                .collect()
        })
        .unwrap_or_default();
    match args.format {
        SimFormat::Json => {
            let questions: serde_json::Map<String, serde_json::Value> = languages
                .iter()
                .map(|l| (l.clone(), json!(question(l))))
                .collect();
            let doc = json!({
                "deck": deck.id,
                "scene": scene,
                "prompt": prompt.id,
                "variant": args.variant,
                "values": values,
                "question": questions,
                "answer": answer.as_ref().map(|a| a.1.clone()).ok(),
                "undecided": answer.as_ref().err(),
            });
            crate::outln!("{}", serde_json::to_string_pretty(&doc)?)?;
        }
        SimFormat::Csv => {
            let mut out = format!("prompt: {} (scene {scene}, deck {})\n", prompt.id, deck.id);
            if let Some(seed) = args.variant {
                out.push_str(&format!("variant: {seed}\n"));
                let shown: Vec<String> = resolved
                    .variant
                    .iter()
                    .flat_map(|v| v.values.iter())
                    .map(|(n, x)| format!("{n} = {}", Num(*x)))
                    .collect();
                out.push_str(&format!("values: {}\n", shown.join(", ")));
            }
            for l in &languages {
                out.push_str(&format!("question ({l}): {}\n", question(l)));
            }
            match &answer {
                Ok((text, _)) => out.push_str(&format!("answer: {text}\n")),
                Err(why) => out.push_str(&format!("answer: undecided: {why}\n")),
            }
            crate::out!("{out}")?;
        }
    }
    if let Err(why) = answer {
        bail!("prompt {id}: the run does not decide the answer: {why}");
    }
    Ok(ExitCode::SUCCESS)
}

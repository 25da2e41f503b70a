//! Runs every exhaustive proof under `cargo test`, printing what each enumerated and how many
//! cases passed; then runs them again in three slices (`geocert prove --shard K/3`), sends the
//! slices through their JSON form and checks that merging them gives the whole run back.

use geocert::internals::proofs::{self, ProofOutcome, Shard};

/// Everything but the wall-clock time, which is the only field a merge may change.
fn comparable(o: &ProofOutcome) -> String {
    let mut o = o.clone();
    o.seconds = 0.0;
    serde_json::to_string(&o).expect("serialisable")
}

#[test]
fn every_proof_passes_and_slices_merge_to_it() {
    let mut failed = Vec::new();
    let mut whole = Vec::new();
    for (name, proof) in proofs::all() {
        let outcome = proof(Shard::WHOLE);
        println!("{}", outcome.summary());
        assert_eq!(outcome.name, name);
        if !outcome.ok() {
            failed.push(outcome.summary());
        }
        whole.push(outcome);
    }
    assert!(failed.is_empty(), "failed proofs:\n{}", failed.join("\n"));

    const N: usize = 3;
    let mut slices = Vec::new();
    for index in 0..N {
        let shard = Shard { index, count: N };
        for (_, proof) in proofs::all() {
            let o = proof(shard);
            assert!(o.ok(), "slice {shard}: {}", o.summary());
            let text = serde_json::to_string(&o).expect("serialisable");
            slices.push(serde_json::from_str::<ProofOutcome>(&text).expect("reads back"));
        }
    }
    let sliced_cases: usize = slices.iter().map(|o| o.cases).sum();
    let merged = proofs::merge_runs(slices).expect("the slices merge");
    assert_eq!(merged.len(), whole.len());
    for (m, w) in merged.iter().zip(&whole) {
        assert_eq!(
            comparable(m),
            comparable(w),
            "{} merged from {N} slices",
            w.name
        );
    }
    println!(
        "{} proofs in {N} slices ({sliced_cases} cases) merge to the whole run, outcome for outcome",
        whole.len()
    );
}

#[test]
fn merge_refuses_incomplete_or_mixed_slices() {
    let proof = proofs::all()[0].1;
    let a = proof(Shard { index: 0, count: 2 });
    let b = proof(Shard { index: 1, count: 2 });
    let c = proof(Shard { index: 0, count: 3 });
    assert!(proofs::merge(vec![a.clone()]).is_err(), "slice 2/2 missing");
    assert!(
        proofs::merge(vec![a.clone(), a.clone()]).is_err(),
        "slice 1/2 twice"
    );
    assert!(
        proofs::merge(vec![a.clone(), c]).is_err(),
        "slices of 2 and 3 mixed"
    );
    assert!(proofs::merge(vec![b, a]).is_ok());
    assert!(Shard::parse("0/3").is_err() && Shard::parse("4/3").is_err());
    assert!(Shard::parse("x").is_err());
    assert_eq!(Shard::parse("3/8"), Ok(Shard { index: 2, count: 8 }));
}

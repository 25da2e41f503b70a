//! Runs every exhaustive proof under `cargo test`, printing what each enumerated and how many
//! cases passed.

#[test]
fn every_proof_passes() {
    let mut failed = Vec::new();
    for (name, proof) in geocert::internals::proofs::all() {
        let outcome = proof();
        println!("{}", outcome.summary());
        assert_eq!(outcome.name, name);
        if !outcome.ok() {
            failed.push(outcome.summary());
        }
    }
    assert!(failed.is_empty(), "failed proofs:\n{}", failed.join("\n"));
}

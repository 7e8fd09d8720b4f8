//! The deck reader's keyword tables: the keywords it reads, those it accepts
//! and lists as ignored (they change nothing cfe computes), and the reasons it
//! gives for the ones it refuses.

/// Keywords accepted and ignored, with why: output requests (cfe writes its own
/// results) and material data no load of the subset uses. Their parameters and
/// data lines are skipped.
pub fn ignored(keyword: &str) -> Option<&'static str> {
    Some(match keyword {
        "NODE FILE" | "EL FILE" | "NODE PRINT" | "EL PRINT" | "CONTACT FILE" | "CONTACT PRINT"
        | "SECTION PRINT" | "NODE OUTPUT" | "ELEMENT OUTPUT" | "CONTACT OUTPUT" | "OUTPUT"
        | "ENERGY PRINT" | "PREPRINT" | "RESTART" => {
            "an output request: cfe writes its own results (VTU, pairs.csv, summary.json)"
        }
        "DENSITY" => "no gravity or inertia load is read, so the density changes nothing",
        "EXPANSION" | "CONDUCTIVITY" | "SPECIFIC HEAT" => {
            "no temperature field is read, so thermal data change nothing"
        }
        _ => return None,
    })
}

/// The reason a known keyword is refused ("is not supported: …").
pub fn refused(keyword: &str) -> &'static str {
    match keyword {
        "PLASTIC"
        | "HYPERELASTIC"
        | "HYPERFOAM"
        | "CREEP"
        | "DEFORMATION PLASTICITY"
        | "VISCOELASTIC"
        | "CYCLIC HARDENING"
        | "USER MATERIAL"
        | "DAMAGE INITIATION"
        | "DAMAGE EVOLUTION"
        | "CRUSHABLE FOAM"
        | "DRUCKER PRAGER"
        | "MOHR COULOMB" => "cfe is linear elastic",
        "FREQUENCY"
        | "DYNAMIC"
        | "BUCKLE"
        | "HEAT TRANSFER"
        | "MODAL DYNAMIC"
        | "VISCO"
        | "STEADY STATE DYNAMICS"
        | "COUPLED TEMPERATURE-DISPLACEMENT"
        | "UNCOUPLED TEMPERATURE-DISPLACEMENT"
        | "COMPLEX FREQUENCY" => "cfe solves static problems only (*STATIC)",
        "AMPLITUDE" => {
            "a step's loads ramp linearly from their earlier value (RAMP); amplitudes are not read"
        }
        "TEMPERATURE" | "INITIAL CONDITIONS" => {
            "cfe reads no temperature field and no initial conditions"
        }
        "EQUATION" | "MPC" | "COUPLING" | "KINEMATIC" | "DISTRIBUTING" | "RIGID BODY" => {
            "cfe has no constraint equations or rigid bodies (join bodies with *TIE or *CONTACT PAIR)"
        }
        "PART" | "END PART" | "ASSEMBLY" | "END ASSEMBLY" | "INSTANCE" | "END INSTANCE" => {
            "part/assembly decks are not read: write the deck flattened (Abaqus: without parts and assemblies)"
        }
        "ORIENTATION" | "TRANSFORM" | "SYSTEM" => "cfe works in the global x, y axes only",
        "SHELL SECTION" | "BEAM SECTION" | "MEMBRANE SECTION" | "BEAM GENERAL SECTION" => {
            "cfe's parts are plane solids (*SOLID SECTION)"
        }
        "CONTACT DAMPING" | "GAP CONDUCTANCE" | "GAP HEAT GENERATION" | "CLEARANCE" => {
            "cfe's contact laws take a penalty, a friction coefficient and nothing else"
        }
        _ => {
            "cfe's deck reader reads *NODE, *ELEMENT, *NSET, *ELSET, *SURFACE, *MATERIAL, *ELASTIC, *SOLID SECTION, *STEP, *STATIC, *BOUNDARY, *CLOAD, *DLOAD, *TIE, *CONTACT PAIR, *SURFACE INTERACTION, *SURFACE BEHAVIOR and *FRICTION (see README, \"Running a CalculiX/Abaqus deck\")"
        }
    }
}

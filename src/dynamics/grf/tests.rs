//! Unit tests of the ground-reaction estimate (`dynamics::grf`).

use super::*;

#[test]
fn centre_of_pressure_of_a_force_through_a_floor_point_is_that_point() {
    // a force F through p0 on the floor at height h, for each up axis
    for up in 0..3 {
        let h = 0.1;
        let mut p0 = Vector3::new(0.3, -0.7, 0.45);
        p0[up] = h;
        let mut f = Vector3::new(12.0, -30.0, 8.0);
        f[up] = 700.0;
        let free = 2.5;
        let w = ForceVec::new(p0.cross(&f) + Vector3::ith(up, free), f);
        let (p, m) = centre_of_pressure(&w, up, h).unwrap();
        assert!((p - p0).norm() < 1e-12, "up {up}: {p} vs {p0}");
        assert!((m - free).abs() < 1e-12);
    }
    let pull = ForceVec::new(Vector3::zeros(), Vector3::new(0.0, -10.0, 0.0));
    assert!(centre_of_pressure(&pull, 1, 0.0).is_none());
}

#[test]
fn a_step_ramps_the_load_from_trailing_to_leading_foot() {
    // left alone, 4 frames of double support, right alone
    let c = |l, r| vec![l, r];
    let contact = vec![
        c(true, false),
        c(true, true),
        c(true, true),
        c(true, true),
        c(true, true),
        c(false, true),
    ];
    let time: Vec<f64> = (0..6).map(|k| k as f64 * 0.1).collect();
    let steps: Vec<Option<Step>> = transitions(&contact, &time)
        .into_iter()
        .map(|t| match t {
            Some(Transition::Step(s)) => Some(s),
            _ => None,
        })
        .collect();
    assert!(steps[0].is_none() && steps[5].is_none());
    let shares: Vec<f64> = steps[1..5]
        .iter()
        .map(|s| s.unwrap().trailing_share)
        .collect();
    assert!(steps[1].unwrap().trailing == 0 && steps[1].unwrap().leading == 1);
    assert!(shares.windows(2).all(|w| w[1] < w[0]), "{shares:?}");
    // symmetric about the middle of the double support
    assert!((shares[0] + shares[3] - 1.0).abs() < 1e-12);
    assert!(shares[0] > 0.8 && shares[3] < 0.2);
}

#[test]
fn double_support_that_is_not_a_step_is_entered_and_left_without_a_jump() {
    // both feet from the start, then left alone, a step to the right, then both feet to
    // the end of the take (standing after a walk): 10 frames at 0.05 s
    let c = |l, r| vec![l, r];
    let mut contact = vec![c(true, true); 3];
    contact.extend([c(true, false), c(true, false)]);
    contact.extend([c(true, true), c(false, true)]);
    contact.extend(vec![c(true, true); 6]);
    let time: Vec<f64> = (0..contact.len()).map(|k| k as f64 * 0.05).collect();
    let t = transitions(&contact, &time);
    // the step (frame 5) is Ren's; its 0.1 s sets the open supports' ramps
    assert!(matches!(t[5], Some(Transition::Step(_))), "{:?}", t[5]);
    let open = |k: usize| match t[k] {
        Some(Transition::Open {
            from,
            to,
            entry,
            exit,
        }) => (from, to, entry, exit),
        other => panic!("frame {k}: {other:?}"),
    };
    // the take starts in double support: the lever rule, leaving towards the left foot alone
    let (from, to, entry, exit) = open(0);
    assert_eq!((from, to, entry), (None, Some(0), 0.0));
    assert_eq!(exit, 0.0, "frame 0 is more than the ramp away from frame 3");
    let exits: Vec<f64> = (0..3).map(|k| open(k).3).collect();
    assert!(exits.windows(2).all(|w| w[1] >= w[0]), "{exits:?}");
    assert!(exits[2] > 0.0 && exits[2] < 1.0, "{exits:?}");
    // the take ends in double support: entered from the right foot alone, lever afterwards
    let (from, to, entry, exit) = open(7);
    assert_eq!((from, to, exit), (Some(1), None, 0.0));
    assert!(entry > 0.5 && entry < 1.0, "frame 7: {entry}");
    assert_eq!(open(12).2, 0.0);
    let entries: Vec<f64> = (7..13).map(|k| open(k).2).collect();
    assert!(entries.windows(2).all(|w| w[1] <= w[0]), "{entries:?}");
}

#[test]
fn a_blend_of_two_loads_is_their_wrenches_interpolated() {
    let up = 2;
    let support = [Support {
        heel: Vector3::new(0.0, 0.0, 0.0),
        toe: Vector3::new(0.2, 0.0, 0.0),
    }];
    let a = FootLoad {
        force: Vector3::new(50.0, 0.0, 600.0),
        cop: Vector3::new(0.02, 0.01, 0.0),
        free_moment: 1.0,
    };
    let b = FootLoad {
        force: Vector3::new(-30.0, 5.0, 200.0),
        cop: Vector3::new(0.18, -0.02, 0.0),
        free_moment: -2.0,
    };
    let mut loads = [a];
    blend(&mut loads, &[b], 0.25, &support, Floor { up, height: 0.0 });
    let e = Vector3::z();
    let want = a.wrench(&e) * 0.75 + b.wrench(&e) * 0.25;
    let got = loads[0].wrench(&e);
    assert!((got.lin - want.lin).norm() < 1e-9 && (got.ang - want.ang).norm() < 1e-9);
    // the centre of pressure lies between the two, weighted by vertical force
    let p = (a.cop * 0.75 * 600.0 + b.cop * 0.25 * 200.0) / (0.75 * 600.0 + 0.25 * 200.0);
    assert!(
        (loads[0].cop - p).norm() < 1e-12,
        "{:?} vs {p}",
        loads[0].cop
    );
}

#[test]
fn in_a_step_each_foot_keeps_a_direction_of_its_own() {
    // z up, floor at 0; trailing foot (0) behind the leading foot (1)
    let up = 2;
    let support = [
        Support {
            heel: Vector3::new(0.0, 0.0, 0.0),
            toe: Vector3::new(0.2, 0.0, 0.0),
        },
        Support {
            heel: Vector3::new(0.6, 0.1, 0.0),
            toe: Vector3::new(0.8, 0.1, 0.0),
        },
    ];
    let params = ContactParams::default();
    let wrench = |l: &FootLoad| l.wrench(&Vector3::z());
    // alone, the trailing foot pushed off (forward and up) near its toe
    let last = FootLoad {
        force: Vector3::new(80.0, 5.0, 700.0),
        cop: Vector3::new(-0.02, 0.0, 0.0), // relative to its toe
        free_moment: 1.0,
    };
    let step = Step {
        trailing: 0,
        leading: 1,
        trailing_share: 0.6,
    };
    // the leading foot brakes (backward and up) near its heel
    let leading = FootLoad {
        force: Vector3::new(-100.0, -8.0, 500.0),
        cop: Vector3::new(0.62, 0.1, 0.0),
        free_moment: -0.5,
    };
    let trailing = FootLoad {
        force: last.force * 0.6,
        cop: Vector3::new(0.18, 0.0, 0.0),
        free_moment: 0.6,
    };
    let w = wrench(&trailing) + wrench(&leading);
    let mut loads = [FootLoad::default(); 2];
    let toe = support[0].toe;
    assign_step(&w, &support, step, &last, toe, up, 0.0, &params, &mut loads);
    for (got, want) in loads.iter().zip([trailing, leading]) {
        assert!(
            (got.force - want.force).norm() < 1e-9,
            "{got:?} vs {want:?}"
        );
        assert!((got.cop - want.cop).norm() < 1e-9, "{got:?} vs {want:?}");
        assert!((got.free_moment - want.free_moment).abs() < 1e-9);
    }
    // sharing w itself would have made the trailing foot brake too
    assert!(loads[0].force.x > 0.0 && loads[1].force.x < 0.0 && w.lin.x < 0.0);

    // the needed force lighter than the trailing foot's share: the trailing foot carries
    // all of it (the leading foot, pressing with nothing, can hold no horizontal force)
    let light = ForceVec::new(Vector3::zeros(), Vector3::new(0.0, 0.0, 300.0));
    assign_step(
        &light, &support, step, &last, toe, up, 0.0, &params, &mut loads,
    );
    assert!((loads[0].force - light.lin).norm() < 1e-9, "{:?}", loads[0]);
    assert!(loads[1].force.norm() < 1e-9, "{:?}", loads[1]);

    // the leading foot pressing lightly: what leaves its friction cone stays behind
    let slip = FootLoad {
        force: Vector3::new(-100.0, 0.0, 50.0),
        ..leading
    };
    let w = wrench(&trailing) + wrench(&slip);
    assign_step(&w, &support, step, &last, toe, up, 0.0, &params, &mut loads);
    assert!((loads[0].force + loads[1].force - w.lin).norm() < 1e-9);
    let h = loads[1].force.xy().norm();
    assert!((h - params.friction * 50.0).abs() < 1e-9, "{:?}", loads[1]);

    // the rest's centre of pressure 10 cm behind the leading heel (outside its support,
    // 5 cm margin): the leading foot keeps its own inside, the trailing foot's moves
    // back to make up the moment, and the two together still give w exactly
    let behind = FootLoad {
        cop: Vector3::new(0.5, 0.1, 0.0),
        ..leading
    };
    let w = wrench(&trailing) + wrench(&behind);
    assign_step(&w, &support, step, &last, toe, up, 0.0, &params, &mut loads);
    assert!(
        (loads[1].cop - Vector3::new(0.55, 0.1, 0.0)).norm() < 1e-9,
        "{loads:?}"
    );
    assert!(loads[0].cop.x < 0.18, "{:?}", loads[0]);
    let given = wrench(&loads[0]) + wrench(&loads[1]);
    assert!((given.lin - w.lin).norm() < 1e-9);
    assert!((given.ang - w.ang).norm() < 1e-9, "{given:?} vs {w:?}");
}

#[test]
fn flight_frames_near_contact_carry_the_spread_force_of_the_nearer_foot() {
    // left stance 0..3, flight 3..9, right stance 9..12; spread 2 frames
    let contact: Vec<Vec<bool>> = (0..12).map(|k| vec![k < 3, k >= 9]).collect();
    let mut up = vec![500.0; 12];
    // the needed force pulls at frame 4 (free fall noise): the push-off's reach ends there
    up[4] = -10.0;
    let loaded = carry_across_spread(&contact, &up, 2);
    let want: Vec<Vec<bool>> = (0..12).map(|k| vec![k < 4, k >= 7]).collect();
    assert_eq!(loaded, want);
    // a short flight: each frame goes to the nearer contact (a tie to the earlier one)
    let contact: Vec<Vec<bool>> = (0..8).map(|k| vec![k < 3, k >= 6]).collect();
    let loaded = carry_across_spread(&contact, &[100.0; 8], 3);
    let want: Vec<Vec<bool>> = (0..8).map(|k| vec![k < 5, k >= 5]).collect();
    assert_eq!(loaded, want);
    // spread 0: only the contact
    assert_eq!(carry_across_spread(&contact, &[100.0; 8], 0), contact);
}

#[test]
fn clamp_keeps_points_inside_and_moves_outside_points_to_the_edge() {
    let s = Support {
        heel: Vector3::new(0.0, 0.0, 0.0),
        toe: Vector3::new(0.0, 0.0, 0.2),
    };
    let inside = Vector3::new(0.03, 0.0, 0.1);
    assert_eq!(s.clamp(&inside, 0.05), inside);
    let ahead = s.clamp(&Vector3::new(0.0, 0.0, 0.5), 0.05);
    assert!((ahead - Vector3::new(0.0, 0.0, 0.25)).norm() < 1e-12);
    let side = s.clamp(&Vector3::new(0.4, 0.0, 0.1), 0.05);
    assert!((side - Vector3::new(0.05, 0.0, 0.1)).norm() < 1e-12);
}

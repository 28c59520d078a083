"""Physics settings that make MuJoCo behave like SimSpark's ODE world (REFERENCE §2.4), with the measurements.

Numbers measured on the 2-core development machine (shared, so wall times vary by 2x) with MuJoCo 4.0.0;
probes: tests/sim/test_world_physics.py, tests/sim/test_world_calibration.py (replays of real 0.7.3
sessions), benchmarks/bench_sim.py.

* **One 20 ms step per cycle, integrator ``discrete``.** SimSpark does one ODE ``dWorldStep`` of 0.02 s per
  cycle. MuJoCo's ``discrete`` integrator solves the constraints and the implicit damping update in one
  velocity-level step, like ODE, and a robot holding every joint stands still at any step (torso height
  constant to 0.1 mm over 10 s at h = 20, 10 and 5 ms). ``implicitfast``, the usual choice, makes the same
  robot rock and hop (feet airborne in 10-25 % of the steps at h = 2, 5, 10 ms; it falls at h = 20 ms):
  the contact impedance comes from the light foot's inertia while the stiff motors weld the foot to the
  whole robot. Sub-stepping buys nothing measurable for standing, and one step keeps ODE's timing (a
  joint at 1 rad/s moves exactly 1.146° per cycle, as the real server's HJ shows). Raw ``mj_step`` per
  cycle: 1 robot 0.03 ms, 22 robots 0.6 ms (CPU time, robots standing).
* **Joint motors = implicit joint damping + a constant force.** ODE's hinge motor is a velocity constraint
  with a force bound (10 N·m). Here the servo force g·(u - q̇) is split into joint damping g (integrated
  implicitly inside the tree factorisation, so it costs nothing) and an applied force g·u; g = kv = 1e5
  N·m·s/rad normally, so a commanded 1.0 rad/s gives 57.30 °/s, -100 is clamped to 6.1395 rad/s, and a
  joint under the full 10 N·m load creeps 1e-4 rad/s. The real server's crouch trace is reproduced to
  0.01° on every joint. MuJoCo's ``velocity`` actuator does the same 3x slower (its gain is a metric term
  outside the tree) and its ``forcerange`` clamp is decided on the explicit force kv·(u - q̇), which
  saturates every light joint at once and overshoots by ~100 rad/s in one step. The 10 N·m bound is kept
  by `sim.effectors.MotorBank`: lowered gains where the bound would be exceeded, a constant ±10 N·m where
  a load overpowers the motor, and a re-solve of the step when the guess was wrong (random ±6 rad/s
  commands flailing a robot against its stops: 0.16 % of the motor torques over 10.5 N·m, the worst 28, since the stops hold under
  runaway commands (f107c45); 0.07 % and 17 before).
* **Joint stops = ODE's** (StopERP 0.8, Bounce 1, FudgeFactor 1e-5), also in `sim.effectors.MotorBank`;
  MuJoCo's limit rows are off. A joint driven into its stop bounces back inside a step later, as the
  real fall trace shows (a hip at 3 rad/s into its 100° stop: 100.24 / 96.81° alternating); MuJoCo's
  soft limit held it past the stop, where every command is ignored (an open-loop turn fell that way).
  Still different under a kick's load (2026-11-28, the real 8 m kick's commands replayed open loop,
  tests/sim/test_real_skill_traces.py): both bounce elastically off the stop, but the real support hip pitch was
  driven 12 deg past its -25 deg stop in one step (the joint inside the stop at the step's start, so no stop row,
  the motor overpowered against a +1.78 rad/s command) and bounced there for three cycles; ours went past a cycle
  earlier, by 2.7 deg, and came straight back, 12.6 deg ahead of the real hip from then on (ours then falls).
  With the support leg and recovery retuned on both servers (2026-11-30, kick_strong_8m_real.toml) ours stands,
  and a second difference shows: the same strike pokes the ball (the foot meets it at 0.87-0.89 m/s, the ball
  moves 0.1-0.7 m) with the ball at +2 cm on the real server and at -0.5..+0.5 cm on ours, and where both kick
  it the real foot lofts it (0.5 m up) while ours drives it flat: the foot's path relative to the ball differs
  by 1.5-2 cm along the kick line on ours, and passes higher on the ball (kick_check from -3 to +4 cm). Traced
  2026-11-30 (``motion-studio real joint-slack kick_strong --ours`` with that file authored, both monitors, the
  ball on its spot): the joint angles agree within 1 deg through the strike and the joints give alike (foot
  40.7 / 37.6 mm at most), but the support foot does not: from the swing's start to the strike (4 cycles) it
  slides back 0.9 cm on the real server and 4.2 cm on ours, the torso pitches 17.2 / 12.5 deg forward, and the
  kicking foot is 2.8 cm short of the real one at the cycle before contact (4.1 / 6.9 cm behind the ball's
  centre). With ``foot_slip_m_s_per_n`` (``sim/physics_candidates/foot_slip.toml``, below) the support foot
  slides 0.8 cm and rises on its toes as the real one to the millimetre (z 13.3-39.5 mm over those cycles, real
  13.7-39.5), the kicking foot is 1.1 cm short, and ours' poke moves from 0 to +1 cm (6.3-6.6 m from -0.5 to
  +0.5 cm; real +2 cm): the Coulomb feet are most of this disagreement.
* **Contacts.** μ = ∞ in SimSpark (slip only through force-dependent slip and soft ERP/CFM, friction even at
  zero normal force inside ODE's 1 mm surface layer: the real FRP shows 24 N sideways with 0 N normal on a
  lifting foot); here Coulomb μ = 2 at the feet (0.95 on the other body parts, below), condim 3,
  elliptic cones: pyramidal cones make ``mj_step`` 2x cheaper but split a standing robot's weight
  unevenly between the feet once μ >= 0.8 (18.4 / 26.8 N at μ = 2, depending on the heading against the
  world axes), elliptic gives 22.60 / 22.60 N like the real server. solimp (0.2, 0.3, 0.001): the
  discrete step makes MuJoCo's default contact almost rigid (0.02 mm sinking), and a foot whose load
  drops then leaves the ground for a whole 20 ms step and bounces (the real crouch keeps contact: ODE's
  1 mm surface layer); with this softer impedance a loaded foot sinks about 0.5 mm and the replayed real
  crouch keeps its feet down (foot force RMS error 5 N instead of 8, fall force RMS 10 N instead of 42).
  Standing: FRP f_z = 22.60 N per foot (REFERENCE: 22.6), c = (±0.003, -0.009, -0.010) m (real:
  (0.00, -0.01, -0.01)); the feet creep 0.4 mm in 10 s (0.01 mm with the default impedance).
* **Ball.** Its own stiff contact parameters win every ball contact (solmix), so it neither sinks into the
  ground nor rolls out early. Free-joint damping gives exactly SimSpark's linear drag 0.01 N·s/m and
  angular drag 5e-5. ODE's bounce (restitution 0.8 above 0.8 m/s) has no stable MuJoCo equivalent at a
  20 ms step (a restitutive spring must be softer than the step, so the ball would sink centimetres), so
  `sim.world.World` adds the rebound after the step: a ball contact approaching faster than 0.8 m/s sends
  the ball off at 0.8 x the approach speed (a 1 m drop rebounds to 0.46 m: 0.64 m less the drag losses).
* **What MuJoCo cannot express (measured 2026-11-25, MuJoCo 4.0.0).** SimSpark's contact rows are ODE's:
  μ = ∞ without the friction-pyramid flag makes the friction rows unbounded equations J_t v⁺ = −slip·λ_t
  (slip 5e-3 m/s per N), the normal row J_n v⁺ = erp·max(depth − 1 mm, 0)/h − cfm·λ_n. MuJoCo's soft rows
  solve J a = aref − R f, so aref = (c − J v)/h, R = cfm/h (normal) and aref = −J v/h, R = slip/h (friction)
  would be ODE's rows exactly, but its ``discrete`` step recomputes aref, R and D inside ``mj_step2`` (after
  ``mjcb_control`` too), so they cannot be rewritten between building and solving; its parameters (solref,
  solimp, impratio) give R relative to the effective inertia, and its cone takes friction away at zero normal
  force. The contact is therefore fitted, not derived: ``motion-studio calibrate`` replays the recorded real
  traces (tests/sim/fixtures) and fits friction, impratio, solimp, solref and no-slip iterations. Found:
  objective 0.943 with these defaults, 0.711 with friction 5.30, impratio 0.157, solimp (0.128, 0.349,
  0.0015), solref (0.032, 1.04) (turns 94.9 -> 91.6° against the real 87.8°, stand-up-back replay 1.50 ->
  0.25, the kick dry run's ball 1.32 -> closer to the real 0.84 m), 0.807 with no-slip 10. Neither is the
  default yet: each breaks skills tuned on these defaults (9 tests: the kick toward a ball 30° off flies
  0.64 m, a back stand-up at 30°, the full-lean walk curve, three of the real-walk replays' bounds), so
  the shipped motions must be retuned on the calibrated world before it replaces this one. The most physical
  candidate so far is ``sim/physics_candidates/ode_friction.toml`` (no-slip post-solve for the robot, a ball
  that cannot slip on foot or ground): the real kick's jam and the stand-ups that stay down are reproduced
  (objective 1.496 -> 0.960 with the kick and 20 m walk fixtures and the ball roll); its header lists what it
  breaks. (With the kick of the current motions it jams the ball: 1.67 m against the real 4.09; the ball contacts
  below fit it.) ``sim/physics_candidates/noslip.toml`` (the no-slip post-solve alone) makes the lying-on-back
  stand-up agree (live transfer: ours 0/10 -> 10/10 at 2.54 s, real 8/10 at 2.54 s) but breaks 4-7 tests of
  skills tuned on these defaults and costs 1.8x the physics CPU; its header has the figures.
  Refitted on every trace of today's world (2026-11-28, 69 traces and the ball roll, the 13 cm walk's among them):
  ``sim/physics_candidates/contact_fit_2026-11-28.toml`` (friction 12.2, impratio 0.21: soft friction with a high
  mu, the direction of the older fit), objective 1.200 -> 1.147. It lets a loaded foot creep as SimSpark's
  force-dependent slip does (standing in a walk's stance the feet squeeze 3 N sideways, real 5 N, these defaults
  33 N; tests/sim/test_contact_creep.py), but 36 tests of skills tuned on these defaults and of other replays fail
  on it; its header has the figures.
* **Feet slip as ODE's (2026-11-29, issue 12; ``foot_slip_m_s_per_n``, not the default).** The friction rows above
  cannot be rewritten inside MuJoCo's step, but an actuator's velocity derivative is solved implicitly with it: a
  velocity actuator with a site transmission measured against a world-fixed reference site is a tangential damper
  at a body point, stable at one 20 ms step on a 0.2 kg foot (a 5 N push on a lone foot box creeps at 6.25 mm/s,
  exactly 5 N / 800 N·s/m). With ``foot_slip_m_s_per_n`` = 0.005 each foot box has one such damper of 1 / slip =
  200 N·s/m per world axis at each of its 8 corners, switched on at the step's start where the corner is below the
  field (ODE's box-plane contact points; SimSpark takes at most 4 per pair, odespace.cpp), whatever its normal force;
  the foot's MuJoCo contact with the field is an explicit pair without friction, and the FRP adds the dampers'
  forces (SimSpark's FRP sums every contact's whole force). Nothing is fitted: SimSpark's foot contacts have mu = inf
  and slip 5e-3 (touchperceptorhandler.rsg; the field's "(setContactSlip 0.1 0.1)" takes one argument, so the field
  keeps the handler's 5e-3, as odecontactjointhandler.cpp's comment says). Measured: the 13 cm walk's stance
  squeezes the feet 4.87 N sideways (real 4.97, these defaults 33.5; tests/sim/test_foot_slip.py); every recorded
  real trace replayed (``motion-studio calibrate``) 1.205 -> 1.030, the same outcome as the real robot in 49 of 67
  replays instead of 42 (the back stand-ups above all); our agent closed loop beside the real one (``motion-studio
  transfer``) walks within 1-7 % of the real speeds (defaults 1-11 %) and turns 1.00 of the real turn (1.05). Not
  the default: our agents fall far more often than on the real server (3 v 3 against standing robots, 16 matches:
  35 falls, nearly all type 4 walking), the back and side stand-ups stand at the second attempt only, and the
  first step's hip yaw-pitch (commanded -5.77 deg in a cycle) now moves -5.77 where the real one moves -4.44: the
  real feet still resist more, most likely by staying in contact where ours lift (the real foot rests deeper).
  ``sim/physics_candidates/foot_slip.toml`` has the figures; ``foot_slip_layer_m`` (a corner holds up to that
  height above the field) measured worse at 1 mm.
* **Body parts slip (2026-11-29, issue 12; ``body_slip_m_s_per_n``, not the default).** SimSpark's body parts have
  the feet's contact (rsg/agent/nao/contactjointhandler.rsg: mu = inf, slip 5e-3 m/s per N). The feet's corner
  dampers on the torso, arm, thigh and shank boxes (the head sphere and the neck keep ``body_friction``) make ours
  behave as the real robot in one respect the Coulomb 0.95 below does not: the back stand-up after scripted falls
  reaches its knees_in phase alike from every fall. The real torso's forward axis is then at z -0.20 / -0.21 in all
  of 10 falls; ours -0.12 to -0.62 with Coulomb (the falls at -0.59 / -0.62 tip forward later), -0.27 to -0.36 with
  slip 0.02 (9 of 10 stand at once). SimSpark's own 5e-3 (up to 0.015) slides too little: ours falls back in every
  start; why the fit is 4 x the nominal slip (ODE's contact count, its soft normal rows) is not found.
  ``sim/physics_candidates/body_slip.toml`` has the figures: the same outcome as the real robot in 46 of 69
  replays (defaults 44), scripted back falls 19 of 20 within 3 s (defaults 17, real 20), and what keeps it from
  being the default: robot types 1 and 4 lying on a side never stand (defaults 8 and 10 of 10, real 9 and 10).
  With the feet slipping too (foot 0.015, body 0.03: ``sim/physics_candidates/slip_fit_2026-11-29.toml``) types 0,
  1, 2 and 4 stand up in the real robot's times (scripted back falls 20/20 in 2.42 s, real 2.44; type 1 on a side
  2.86 s, real 2.94), calibrate 1.038 and 48 of 69; type 3 on a side then never stands (real 8 of 10), and our 3 v 3
  against standing robots scores 16 goals in 16 matches instead of 27 (turns and pushes tuned on the defaults).
* **Ball contacts, fitted on the real kick and the real roll (2026-11-26).** SimSpark's ball contacts have
  μ = ∞ with force-dependent slip 0.3 m/s per N (the ball's 0.6 averaged with 5e-3), so the tangential force
  a ball contact can carry grows with the slip, not with the normal force. Two consequences MuJoCo's Coulomb
  cone cannot give with one μ: (1) on the ground (normal force = the ball's weight, 0.26 N) a launched ball
  stops slipping within a step and rolls at once at 5/7 of its speed: the real ball stops after 0.677 m per m/s
  at 2, 4, 6 and 8 m/s. With MuJoCo's max(ball, ground) = 2 ours slid longer the faster it went: 0.6847,
  0.6858, 0.6969, 0.7087 m per m/s (+1.1 to +4.7 %). An explicit ball-field contact pair with μ = 10
  (``ball_ground_friction``) rolls it at once: 0.6847 at every speed (+1.1 %). (2) A kicking foot presses the
  ball with ~30 N; μ = 2 there gripped the ball between a foot whose toes were sweeping down and the ground, so
  it was pushed into the ground (10 mm deep) and rolled off at 5/7 of its launch speed: the real kick's
  commands replayed moved our ball 2.43 m, the real one 4.09 m. The ball's priority (``ball_priority`` 1) lets
  its own μ decide its robot contacts instead of MuJoCo's max with the foot's 2; replaying the real kick fixture
  (tests/sim/fixtures/real_0.7.3_skill_kick*.jsonl.gz, motions 66e41c9) gives 3.87 m at μ 0.3, 4.01 at 0.5,
  4.00 at 0.7 and 2.43 at 1.0 and above (the jam returns), so μ = 0.5 is the middle of the agreeing range.
  Live (``motion-studio transfer --case kick --case kick_left``): real 4.086 m, ours 4.004 (was 2.438). Probe:
  ``motion-studio calibrate --only kick --only ball_roll --details``.
  Gentle contacts (scripts/real_ball_push.py, our agent on both servers): a 3 s walk_left into a ball beside the
  left foot pushes the real ball 1.48 m, ours 1.68 m (mu 2 before: 0.86 m); walk_forward into a ball 0.3 m ahead
  (on the right-foot line, centred, on the left-foot line): real 3.49, 1.72, 2.10 m, ours 3.58, 3.58, 3.13 (mu 2:
  1.00, 2.42, 3.53). The untuned kick of the ``kick_dryrun_simcmds`` fixture got worse (real 0.84 m, ours 1.32 ->
  1.70 m): one Coulomb mu is not SimSpark's force-dependent slip (see the xfail in
  tests/sim/test_real_skill_traces.py). Skills tuned on mu 2 near the ball behaved differently (WalkToBall's
  line-up beside the ball, the kick-off: strict xfails in tests/scenarios, both mended since).
  Still different: the real ball flies (launched 4.4 m/s forward and 1.2 m/s up, lands after 0.14 s and rolls
  at 3.7 m/s); ours leaves the foot rolling at 4.0-4.2 m/s, so the distance agrees but not the path. The real
  kicking hip is also thrown back 7 deg a step for two steps right after the strike (rlj3 24.8 -> 17.9 -> 12.2
  while commanded forward); ours followed its commands to 46 deg, with or without the ball, and the open-loop
  replay then fell at cycle 162 where the real robot stays up. (Found 2026-11-28: the real foot, 13-19 mm below
  its joint angles, scrapes the ground; see "The kicking foot meets the ground" below.)
* **Ball contacts, fitted on pushes too (2026-11-26, issue 12).** With the contact above a walking foot pushed
  ours far harder than the real ball: the dribble's first touches, replayed with the same joint commands on both
  servers (``motion-studio real skills dribble_push --replay-sim``, fixture
  tests/sim/fixtures/real_0.7.3_skill_dribble_push_simcmds.jsonl.gz), moved the real ball 2.71 m and ours 4.33 m:
  ours left the foot at 3.0 m/s, the real one at 1.2 m/s. MuJoCo's default solref (0.02, 1) recovers the
  penetration of a foot moving 1-2 m/s (2-4 cm in a 20 ms step) within one step, which adds metres per second; the
  real ball's contact (soft CFM 0.025 with the robot, 0.05 with the ground) lets the ball sink and gives less back.
  ``motion-studio calibrate --parameters ball --only skill_kick_left --only skill_kick_strong_left --only
  kick_dryrun --only ball_roll --only dribble_push --only ball_beside`` (12 generations of 10, from a first 14 that
  fitted without the restitution: solref (0.0436, 0.96), solimp (0.061, 0.852), which shortened the kick to 3.49 m)
  gave ``ball_friction`` 0.268, ``ball_solref`` (0.0454, 0.648), ``ball_solimp`` (0.1126, 0.7733) and a
  restitution of 1.0, which ``ball_robot_restitution`` takes: on the field it kept its 0.8 (a 1 m drop rebounds
  to 0.70 m at 1.0, 0.64 m less the drag at SimSpark's 0.8). Real / ours before / ours now: dribble push 2.71 / 4.33 / 2.62 m, walk_left into the
  ball beside the foot 1.48 / 1.68 / 1.47 m, the shipped kick 4.09 / 4.01 / 3.88 m, the ball's roll 0.677 /
  0.685 / 0.677 m per m/s, the resting ball's height 0.0403 / 0.0416 / 0.0401 m; the untuned kick of the
  ``kick_dryrun_simcmds`` fixture, which jams the real ball, got worse (0.84 / 1.70 / 1.78 m).
  Still different (measured 2026-11-27): the dribble push agrees in its end only. Replayed, the real ball's first
  touch moves it 1.0 m and a second touch 1.7 m more; ours leaves with one touch that carries it 2.4 m. Closed loop
  (``motion-studio real skills dribble``, type 0, 10 m) the real dribble takes 28-46 s in 5 runs, ours 16-17.5 s:
  the real ball stays near the feet (within 0.5 m of the torso 44-58 % of the time, ours 21-33 %) and drifts out
  of the walking line, so the real robot lines up again more often; ours rolls ahead and is walked after.
  Why it drifts (measured 2026-11-27, the real closed-loop dribble's commands replayed here, fixture
  real_0.7.3_skill_dribble_push): the feet reach the ball as on the real server (torsos within 6 mm up to the
  first touch), the landing left foot grazes it first on both, but the real ball then stays put (pressed between
  a planted foot and the ground, SimSpark's unbounded friction holds it) where ours rolls on 0.3 m/s to the right;
  so the right foot meets the real ball with its inner front corner, 14 deg left, and ours square, 6 deg right.
  No single ball friction, solref or restitution turns this touch without turning the simcmds touch with it
  (strict xfail in tests/sim/test_real_skill_traces.py).
  Grown since (measured 2026-11-30, ``motion-studio real skills dribble_push --replay-sim``: our agent's commands
  on ours, replayed on the real server; both monitors): the ball moves 1.15 m on the real server in the case's 8 s
  and 3.50 m on ours. The landing left foot grazes the ball at 0.56 m/s downward: the real ball moves 0.08 m/s,
  ours squirts out sideways at 1.4 m/s (0.22 m/s with rigid joints, ``sim/physics_candidates/rigid_joints.toml``;
  0.72 m/s without the robot rebound, ``ball_robot_restitution`` 0). The right foot then meets it at 2.0-2.1 m/s:
  both balls move 2.0 m/s in the contact cycle, then the real one rolls off at 1.14 m/s, ours at 3.34 m/s (1.89
  m/s without the rebound): the real walking touch is nearly inelastic. The rebound alone is not it: a restitution
  growing from 0 at 2.0 m/s of approach to 1.0 at 2.8 m/s (scratch, not kept) made the recorded replays agree less
  (``motion-studio calibrate --details``: the kick traces 0.59 -> 0.78, the ball 1.2 -> 1.78 m apart; the recorded
  push ``dribble_push_simcmds`` 0.74 -> 0.81) and left the slowed kicks as they were (asked for 1 / 2 m: real 0.82 /
  1.34 m, ours 1.30 / 1.77 m, with the rebound or without). A grippier ball (``ball_friction`` 0.6 / 1.5 for 0.268)
  trades the traces against each other as the fit found (calibrate on the 20 kick, push and ball-beside traces:
  objective 0.861 -> 0.925 / 1.170; the slowed kicks agree better, kick_1m 0.65 -> 0.23 / 0.28 and kick_2m 0.47 ->
  0.08 / 0.26, the full kicks less, 0.59 -> 0.84 / 1.44). Next: a ball-foot contact that holds as SimSpark's
  unbounded friction with force-dependent slip does (not one Coulomb mu), fitted on every ball trace; the dribble
  and the matches were tuned on this touch.
  Also different before the joint drift below (measured 2026-11-27, ``python -m motion_studio.realserver.kick_check
  kick --offsets-cm=0,0.5,0.8,1,1.5``): the shipped kick from 0.5-1.0 cm beyond its spot went 1.65-1.86 m here and
  3.93-4.05 m on the real server: up to the swing the two robots agreed to a tenth of a degree per joint, but at the
  strike our kicking foot ran 7-9 mm higher than the real one, met the ball with its centre inside the foot box
  and pressed it along the ground. Why: ODE's joints give; see "Joints give" below.
* **Joints give: ODE's joint drift on the legs' ball contacts (2026-11-28, issue 12; `sim.joint_slack`).** ODE
  solves its joint rows at the velocity level with the step's starting Jacobians and then moves every body in a
  straight line, so a body turning on a lever leaves its joints' arc by about ½ r w^2 h^2 a step, and the world ERP
  (0.2, SimSpark keeps ODE's default) takes back a fifth of what has gathered each step. MuJoCo's joints are
  generalized coordinates and never separate. ``motion-studio real joint-slack CASE... --ours`` (our kinematics of
  the monitor's torso and the HJ angles against the monitor's body, on both servers) measures it; the model in
  `sim.joint_slack` (nothing fitted: h and ERP are ODE's) gives, real / ours, median / p90 / max [mm]: walk_forward
  right foot 3.4 / 5.5 / 6.2 against 3.5 / 5.5 / 6.1, left foot 3.6 / 6.0 / 6.7 against 3.5 / 5.5 / 6.0, right
  shank 2.6 / 3.7 / 4.5 against 2.7 / 3.6 / 4.2; turn_left feet 1.5-1.6 / 3.4-3.6 / 4.1-4.5 against 1.5-1.6 /
  3.6-3.7 / 4.1-4.2; the kick's last three cycles before the strike per axis within 1.2 mm for foot, shank and
  thigh (foot z 7.3, 13.3, 18.6 against 7.5, 13.3, 19.0); kick_strong foot max 32.6 against 29.2. Where it acts:
  only on the ball. Each leg geom (thighs, shanks, feet) has a twin that collides with the ball alone and is moved
  by its body's drift; the originals keep the ground and the other robots. The real stance foot sinks into the
  ground by its drift (the real monitor's standing-leg foot centre 4-8 mm above the field instead of 10) while the
  torso keeps its height; moving the originals instead lifted our walking torso 2.6-3.0 mm above the real one and
  turned the replayed real walk 6.9 deg in 3 s (real 0.05), 29 tests failed. The monitor shows the drifted centres
  (``World.body_centres``), as the real one does. Measured with the kick (``kick_check kick --offsets-cm``, real /
  ours): the real kick has two regimes along its line, 3.24-3.30 m at -0.5..-0.8 deg from 1 cm to 2.5 mm short of
  the spot, 3.84-4.39 m at -6.6..-9.0 deg from 1 mm short to 3 cm beyond; ours now 3.88-3.90 m at -2.9 deg and
  4.32-4.37 m at -8.2..-8.3 deg with the boundary in the same place (before: 3.88 m at -2.9 deg up to +1 mm, a
  pocket of 1.3-1.9 m from +2 mm to +1 cm, 4.4 m from +1.5 cm), but with a 3 mm pocket on the boundary (1.2-2.3 m,
  the ball scooped up from -1 to +1 mm, where the real spot lies). The pocket's cause is not the drift: one cycle
  before the strike our stance toe leaves the ground for a step and the robot drops 4.4 mm where the real one
  stays (ODE's 1 mm surface layer keeps a lightly loaded toe in contact; MuJoCo has no dead band), so our foot
  meets the ball 4 mm lower than the real one, nearer the foot box's top face than its front face (strict xfail in
  tests/motion_studio/test_calibrate.py). The long kick now goes 4.85-5.33 m from -0.5 to +1 cm (real 5.1-5.6 m
  from the spot to +2 cm; 4.4-4.6 m before), but ours falls from +1.5 cm. Ours 3 v 3 against standing robots and
  the walks, turns and stand-ups are unchanged within their spread (see the closing note of issue 12).
  ``sim/physics_candidates/rigid_joints.toml`` switches the drift off; its header has what that changes.
* **The kicking foot meets the ground where its drift puts it (2026-11-28, issue 12; ``swing_drift_ground_m``).**
  ODE's bodies are where the drift puts them, for the ground too; ours keeps the ground on the joints' geometry
  (above: moving the stance feet lifted the walking torso and turned the real walk). After a kick's strike the
  real kicking foot, 13-19 mm below its joint angles and still swinging down, scrapes the ground: the real hip is
  stopped and thrown back (rlj3 24.8 -> 17.9 -> 12.2 deg while commanded on) and the robot stands; ours followed
  its commands (25.1 -> 32.1 -> 39.2) and fell about 3 s later when the real kick's commands were replayed open
  loop. Now a foot without weight in the last step whose drift exceeds ``swing_drift_ground_m`` meets the field
  through its ball-side twin (``World._swing_feet_meet_the_field``). The threshold keeps the mechanism where the
  drift is a kick's: every unloaded foot (no threshold) turned the open-loop walks (walk_backward 24 deg against
  the real -0.2, walk_right -89 against 14), their swing feet drifting 3-7 mm onto a ground that then held them.
  ``motion-studio calibrate`` (every real trace; 0 = as the real server) by threshold: off 1.264, 5 mm 1.114,
  7.5 mm 1.247, 1 cm 1.091, 1.25 cm 1.041, 1.5 cm 0.997, **2 cm 1.006**; at 2 cm only the kick traces change
  (kick, kick_left, kick_strong, kick_strong_left, kick_4m 3.07 -> 0.59, kick_beyond_8mm 2.57 -> 0.28; kick_3m
  stays 2.82: ours still falls after it), at 1-1.5 cm some stand-up, side and walk traces move too (mixed). The
  real kick's commands replayed: the kicking hip two and three steps after the strike 20.8 and 21.7 deg (real 17.9,
  12.2; off 32.1, 39.2; 1 cm 24.0, 24.4), upright as the real robot; the ball 3.0 m (real 4.09 from the spot
  before 2026-11-28, ours' pocket; off 1.99 m). Ours 3 v 3 against standing robots, seeds 0-31: 56 goals, our
  falls 7 (off: 52, 6).
* **Body-part friction, fitted on the real lying-on-back stand-up (2026-11-26, issue 12).** SimSpark's robot
  contacts slip in proportion to their tangential force (force-dependent slip 5e-3 m/s per N, μ = ∞), so a body part
  pushed hard along the ground slides while the feet of a walk, whose tangential forces stay small, hold. Lying on
  its back (transfer case ``standup_front``), the real robot's sit-up and crouch carry the torso 0.30-0.37 m forward
  over its feet (recorded start 2: x -8.367 -> -8.002 m over the 64 cycles from the sit-up's start); with μ = 2 on
  every geom ours got at most 0.17 m forward, kept its weight behind its feet and fell back: 0 of 10 transfer starts
  stood (real 8 of 10). The feet keep ``friction`` = 2; every other robot part (torso, head, arms, thighs, shanks:
  the buttocks are the thigh boxes, up to ~50 N on each while sitting up) has ``body_friction`` = 0.95, and so have
  the field and the goals (MuJoCo takes the larger of the two geoms' friction, so the static geometry takes the
  lower of the two robot values). Ours now slides 0.30 m in start 2 and stands. Measured (our agent closed loop on
  the transfer's lying starts 0-9, seeds 0 and 1; first-attempt stands of 10, lying on the
  back): μ 0.5 -> 0 (9 stand at the second attempt, 5.6 s), 0.8 -> 10 / 7, 0.85 -> 8, 0.9 -> 10 / 10, 0.93 -> 3 / 3,
  0.95 -> 10 / 10, 0.97 -> 8 / 10, 1.0 -> 9 / 9, 1.1 -> 0, 1.2 -> 2, 2 (before) -> none stands at all; lying on the
  front 10/10 at every value from 0.8 to 1.2. The outcome of one start flips with a few hundredths of μ (the real
  robot is as marginal: of its 10 starts 6 stand at once, 2 at the second attempt, 2 never), so 0.95 is a value
  inside the band 0.8-1.0 where it mostly stands, chosen where the suite's other back stand-ups (the workbench's
  lying pose, the rollout's seeded fall) stand too (they fail at 0.8, 0.85, 0.9, 1.0). Keeping the arms at μ 2
  (hands gripping) makes it worse (0.8 -> 0 first-attempt stands). Live, ``motion-studio transfer --starts 10``
  (real rcssserver3d 0.7.3 beside ours): lying on the back real 8/10 in a median 2.54 s, ours 10/10 in 2.48 s (was
  0/10); lying on the front real 10/10 2.56 s, ours 10/10 2.55 s (start 6 at the second attempt); walks, turns,
  kicks and the 20 m walk as before, to the printed digit (1.07 / 1.01 / 1.04 / 1.05 of the real speeds, turns 1.05,
  TurnBy 1.03, kick 4.00 m against 4.09, 20 m in 34.4 s against 37.2). Same outcome as the real robot per start: 8
  of 10 (the real starts 5 and 9 never stand; ours do). Still different: the real robot lying still creeps ~8 cm
  forward in some starts (2: its feet and head alternately carry it) and not in others (9); ours does not creep
  (Coulomb friction has no slip below the cone). The open-loop replays of the recorded real runs (``motion-studio
  transfer --replay``) are unchanged by it: back 2/10, front 8/10 (they replay the real agent's commands, timed on
  the real robot's state). On the stand-up tuner's own scripted falls onto the back
  (motion_studio.realserver.rollout_standup.StandUpBench, seeds 0, 1, 3, 10 each; real 8 + 9 + 10 = 27/30) ours
  stood in 7 + 9 + 8 = 24/30 with μ 2 and 8 + 7 + 7 = 22/30 with 0.95 (0.5 to 1.2: 21-23/30, the starts that fail
  change with μ); onto the front 20/20 with both. Per transfer start
  (torso x gained in the 70 cycles from the lowest point before the sit-up): the real
  robot is bimodal, 0.40-0.42 m in the six starts that stand at once, 0.24-0.28 m in the four whose first attempt
  fails (0 and 1 stand at the second, 5 and 9 never); ours 0.34 m in every start (μ 2: 0.17 m), so it stands in all.
  Lying still before the sit-up the real torso moves -0.02 to +0.11 m, ours -0.01 to -0.11 m (backward, with either
  friction). What splits the real robot's two modes is not found yet.
* **Lying on the back with the legs curled (measured 2026-11-26, not explained).** roll_to_back (a robot on its
  side rolls onto its back) ended with the hips at 99 deg and the knees at -129 deg; standup_back played from
  there stood the real robot up in 10 of 10 side falls (``motion-studio transfer --case standup_side --motions
  d123d5e``, median 3.50 s) and ours in 1 of 10: ours rose to 0.27 m and fell back onto its back in the stand-up's
  knees_in phase every time. From a flat back (roll_to_back's third phase since 07e539d) both stand: real 10/10 in
  3.74 s, ours 9/10 in 3.64 s. The contact of the curled feet and buttocks with the ground (ODE's force-dependent
  slip against one Coulomb mu here) is the likely difference; not measured further.
* **Walking feet land harder and a cycle earlier on the real server (measured 2026-11-29, not matched).** In the
  real forward walk (fixture ``real_0.7.3_skill_walk_forward``) every joint reaches its command two messages later
  to within 0.3 deg, except the left hip pitch (llj3), which lags 1.1 deg in the step of every left landing (its
  10 N·m motor saturates); the real gait is not symmetric: the left foot lands with 127.5 N in its first FRP, the
  right one with 67.3 N, a cycle early, while the left foot still touches (-0.3 N); steps alternate 4 and 6
  cycles. Replayed here both feet land with 81-86 N a cycle after the other foot left (our swing foot is 0.8 mm
  above the ground where the real one touches), steps of 5 and 5, and the hip needs 7.8 of its 10 N·m: no lag,
  so our hip ends 1 deg further per step from the real one (1.9, 2.9, 4.0 deg after three left landings) and the
  open-loop walk falls at 4.8 s. Neither stiffer contacts (solimp 0.5/0.6 or 0.9/0.95: the landing's force moves
  to the next cycle, 6.1 N·m), ODE's surface layer as margin (1 or 2 mm) nor the feet's slip candidate bring the
  lag (walking and dribbling traces ending as the real ones: 8 of 17 with the defaults, 7-9 with these).
  (`motion-studio calibrate --only skill_walk --only skill_dribble --only skill_kick_3m`.)
  `motion-studio calibrate --only skill_walk_forward --divergence` shows it (2026-11-29): llj3 is the first joint
  past 1 deg (1.50 s after the skill's start), -3.97 deg at 2 s, -9.29 at 3 s, one step of about 1.1 deg per left
  landing while every other joint stays within 1.4 deg; the real torso repeats its height to 0.02 mm every gait
  period from the third second on (0.32985 m every 10 cycles), ours creeps upright (up axis 0.97 -> 1.00) and
  falls at 4.78 s. Each step is the landing: commanded -3.835 rad/s (-4.39 deg a cycle), the real hip moves
  -2.93 deg, ours -4.03, the left foot's first FRP 127.5 N against our 81.2 (messages 120 -> 121), and five cycles
  before, where the real foot has left the ground (-0.3 N), ours still carries 9.2 N. The same staircase, and a fall
  within 2-7 s, with every candidate file (foot_slip, body_slip, slip_fit_2026-11-29, noslip), a softer, harder or
  wider impedance (solimp 0.1-0.5 / 0.2-0.6, width 1-2 mm; from 0.7 / 0.8 on the right knee leaves first), motor
  bounds of 7-9 N·m for every joint (the staircase comes sooner) and a hard landing made by direct solref
  (-300..-1000, -50..-100) with impedance 0.95, or ODE's 1 mm layer with a stiff impedance (surface_layer_m 0.001,
  solimp 0.5-0.9: the standing torso at 0.38383-0.38398 m, as the real one, but from 0.7 on the walk hops 3 cm):
  ODE's row itself as two normal-only MuJoCo pairs per slipping foot (a damper of 1 / h from depth 0 and a spring
  of ERP / h² = 1000 /s² past the 1 mm layer, impedance 0.9975 = ODE's CFM / h, feet slipping at 5e-3) stands at
  0.38402 m but bounces: a stance foot reads 0 N every other cycle where the real one carries 20-60 N, and the walk
  falls at 2-4 s. What gives the real hip its landing load is still not found. Standing, the real torso is 0.63 mm lower than ours (0.38387 / 0.38450 m):
  ODE's contact row pushes back only beyond its 1 mm surface layer (ERP 0.6, soft CFM 1e-4: at rest 1.02 mm deep)
  but stops a touching foot from depth 0, which MuJoCo's reference distance cannot express (a negative margin,
  ``surface_layer_m``, moves the onset to the same depth).
  Cycle by cycle (2026-11-29, ``motion-studio calibrate --only skill_walk_forward --divergence --cycles 2.2:2.6``):
  the real walk has a flight cycle before every left landing, both feet off the ground (no left FRP, the right one
  -0.4 N), in which its torso drops 5.2-5.3 mm; ours still stands on the right foot with 8-10 N there and drops
  3.1-3.5 mm, so the real left foot lands with 127.6 N and ours with 73-84 N. Before each right landing it is the
  other way round: the real right foot lands a cycle earlier (67 N while the left lifts), ours a cycle later with
  83-96 N. While walking our torso is 1-7 mm lower than the real one on the same joint angles (standing it is 0.6 mm
  higher). Also tried today, each with the same staircase and a fall at 3.3-7.0 s: ``surface_layer_m`` 0.3, 0.5
  and 0.7 mm at the default impedance; direct solref (-10000, -500) and (-10000, -1000) at impedance 0.95 (the
  feet hop: 0 N on both from 0.06 s); swing feet meeting the field through their drifted twins at 1-3 mm
  (``swing_drift_ground_m``; the twins then carry the stance, the torso stands 2-4 mm above the real one, and the
  FRP, which reads the originals only, shows 0 N), with ``joint_slack_erp`` 0.3 / 0.4 (less drift) as well.
  Why the lag adds up (2026-11-30, ``--cycles 1.0:2.2 --joints llj3``): the real hip is 1.16-1.18 deg behind its
  course after each left landing and back on it two cycles later, because the real agent, closed loop, commanded
  the lag back; replayed open loop, our hip has no lag to make up and is driven those 1.1 deg past its course at
  every left landing (ours - real at the same phase of successive strides: -0.6, -1.9, -3.0, -4.0 deg).
  Tried 2026-11-30 (a scratch patch, not kept): the feet's own ground geoms moved by the vertical part of their
  drift, all of it or half (the real stance foot's centre sits 2-6 mm below its joint angles): our walking torso
  then stands 0.1-3 mm above the real one instead of 1-7 mm below, but the landings keep their timing (the right
  foot a cycle after the real one, 9.5 N left on the lifting foot, no flight cycle) and the replay falls sooner,
  at 4.26 / 3.08 s (4.78 without).
* **Force-dependent slip at SimSpark's own value on every robot box (measured 2026-11-29, not kept).** With body and
  feet at 5e-3 m/s per N (rsg/agent/nao/contactjointhandler.rsg) the real front stand-up's open-loop replays 2 and
  3 stand (defaults and slip_fit_2026-11-29: fall forward out of the crouch) and ours' loaded joints lag as the real
  ones do: in start 2 the hip yaw-pitch, whose legs drag on the field, leads the real joint by up to 24 deg at the
  defaults and trails it by 5-11 deg at 5e-3; the knees end the rise 14 deg ahead of the real ones at the
  defaults, 6 deg at 5e-3. But every
  recorded back stand-up then falls back (`motion-studio calibrate`: the same outcome as the real robot in 36 of
  69 skill traces; defaults 44, body 0.01 with feet 5e-3 44, slip_fit_2026-11-29 48).
* **Drag on robots.** SimSpark applies F = -0.01 v and τ = -0.01 ω to every body. Here the whole-body part
  is free-joint damping of the torso (N_bodies x 0.01 on the linear and angular dofs), exact for a rigid
  translation; the drag of limbs swinging relative to the torso is left out (at most 0.06 N·m at full
  joint speed, against 10 N·m motors).
"""

from __future__ import annotations

import os
import tomllib
from dataclasses import dataclass, fields, replace
from pathlib import Path
from agent.protocol.constants import CYCLE_S
from sim.errors import PhysicsFileError


@dataclass(frozen=True)
class PhysicsParams:
    """Numbers of the MuJoCo world; see the module docstring for why each has its value."""

    cycle_s: float = CYCLE_S
    """Simulated time per agent cycle [s] (REFERENCE §1)."""
    substeps: int = 1
    """MuJoCo steps per cycle; timestep = cycle_s / substeps."""
    gravity_m_s2: float = 9.81
    """Gravity magnitude [m/s²] (REFERENCE §2.4)."""
    motor_kv: float = 1.0e5
    """Servo gain of the joint motors [N·m·s/rad]: steady velocity error = load / kv."""
    motor_active_set_passes: int = 3
    """At most this many physics solves per step to settle which motors are saturated."""
    motor_torque_tolerance: float = 0.05
    """A servo force up to (1 + tolerance) x the bound is accepted without a re-solve."""
    friction: float = 2.0
    """Coulomb friction coefficient of every contact (SimSpark: unbounded, see the docstring)."""
    body_friction: float | None = 0.95
    """Coulomb friction of the robot's body parts other than the feet (torso, head, arms, thighs, shanks): a foot's
    contacts keep ``friction``, every other robot contact with the field, the goals or another body part has this
    (the static geometry gets the lower of the two; MuJoCo takes the larger of two geoms'). None = ``friction``
    everywhere. Fitted on the real lying-on-back stand-up, see "Body-part friction" in the docstring."""
    contact_condim: int = 3
    """Contact dimensionality (3 = normal + 2 tangential)."""
    contact_solref: tuple[float, float] = (0.02, 1.0)
    """solref of every contact (time constant [s], damping ratio)."""
    contact_solimp: tuple[float, float, float, float, float] = (0.2, 0.3, 0.001, 0.5, 2.0)
    """solimp of every contact: soft enough that a loaded foot sinks ~0.5 mm, as ODE's 1 mm surface layer
    lets it (calibrated on the real 0.7.3 traces, see the module docstring)."""
    surface_layer_m: float = 0.0
    """Depth a contact with static geometry may reach before it pushes back [m] (ODE's contact surface layer;
    SimSpark: 0.001). Done as MuJoCo's margin/gap of the static geoms: detected from ``surface_layer_m``
    above, active only below ``surface_layer_m`` deep, and the reference is that depth."""
    cone: str = "elliptic"
    """Friction cone: "elliptic" or "pyramidal"."""
    impratio: float = 1.0
    """MuJoCo's frictional-to-normal impedance ratio of elliptic cones (> 1: stiffer friction, less creep)."""
    ball_friction: float = 0.268
    """Coulomb friction of the ball's contacts with robots, goals and walls (the ball's priority makes its value
    decide; SimSpark: unbounded, force-dependent slip 0.3 m/s per N). Fitted with the ball's contact (see the
    docstring: "Ball contacts, fitted on pushes too")."""
    ball_solref: tuple[float, float] = (0.0454, 0.648)
    """solref of the ball's contacts: softer than MuJoCo's default (0.02, 1.0), whose deep-penetration recovery
    launched a ball pushed by a walking foot at 3 m/s where the real one rolls off at 1.2 m/s (fitted, see the
    docstring)."""
    ball_solimp: tuple[float, float, float, float, float] = (0.1126, 0.7733, 0.001, 0.5, 2.0)
    """solimp of the ball's contacts (fitted with ``ball_solref``): the resting ball sinks 2 mm, as the real one
    (0.0401 m against the real 0.0403; MuJoCo's stiff default left it at 0.0416); it wins the parameter mix of
    every ball contact."""
    ball_priority: int = 1
    """MuJoCo geom priority of the ball: 0 = its friction mixes with the other geom's (MuJoCo takes the larger);
    1 = the ball's friction, condim, solref and solimp decide each of its contacts alone."""
    ball_ground_friction: float | None = 10.0
    """Coulomb friction of the ball on the field plane alone (an explicit MuJoCo contact pair, so the ball's
    foot contacts keep ``ball_friction``); None = no pair, the field plane mixes like any other geom."""
    ball_ground_solref: tuple[float, float] | None = None
    """solref of the ball-field pair (None: ``ball_solref``)."""
    ball_ground_solimp: tuple[float, float, float, float, float] | None = None
    """solimp of the ball-field pair (None: ``ball_solimp``)."""
    ball_restitution: float = 0.8
    """Ball bounce on the field, goals and walls (REFERENCE §2.4)."""
    ball_robot_restitution: float = 1.0
    """Restitution of ``sim.world``'s rebound of the ball off a robot: SimSpark's bounce is 0.8 there too, but with
    the soft contact above MuJoCo has already absorbed part of the impact when the rebound is added, and the fit
    on the real kick, pushes and roll put it at 1.0 (0.9993; the fit's range ends at 1.0)."""
    ball_min_bounce_speed_m_s: float = 0.8
    """Normal approach speed above which the ball bounces [m/s]."""
    ball_linear_drag_n_s_m: float = 0.01
    """Ball linear drag [N·s/m]."""
    ball_angular_drag_nm_s: float = 5e-5
    """Ball angular drag [N·m·s/rad]."""
    body_linear_drag_n_s_m: float = 0.01
    """Drag per robot body [N·s/m] (REFERENCE §2.1)."""
    body_angular_drag_nm_s: float = 0.01
    """Angular drag per robot body [N·m·s/rad]."""
    solver_iterations: int = 50
    """Main solver iterations (Newton)."""
    joint_slack_erp: float | None = 0.2
    """ODE's world ERP for the joint drift of `sim.joint_slack` (where ODE's straight-line update leaves each robot
    body, a fifth of the gathered drift taken back per step; the legs meet the ball there, and the monitor shows
    it); None or 0 = joints that never give, MuJoCo's own. See "Joints give" in the docstring."""
    swing_drift_ground_m: float | None = 0.02
    """A foot that carried no weight in the last step meets the field where ODE's joint drift puts it, once its
    drift (`sim.joint_slack`) exceeds this [m]: its ball-side twin then collides with the field too. None or 0 = off.
    Needs ``joint_slack_erp``. 2 cm: a kick's swing foot passes it right after the strike (13-19 mm at the
    strike), a walking foot (3-7 mm) or a stand-up never does; see "The kicking foot meets the ground" in the
    docstring for the threshold scan. ``sim/physics_candidates/swing_drift_ground.toml`` holds 1 cm."""
    foot_slip_m_s_per_n: float | None = None
    """SimSpark's force-dependent slip of a foot's contacts with the field [m/s per N] (0.005: contactjointhandler.rsg
    and the field's default, ODE's mu = inf): each foot corner below the field's surface is held by a tangential
    damper of 1 / slip N·s/m, solved implicitly with the step, and the foot's MuJoCo contact with the field carries
    the normal force alone. None = MuJoCo's Coulomb friction (``friction``), the default: see "Feet slip as ODE's" in
    the docstring for why."""
    body_slip_m_s_per_n: float | None = None
    """Force-dependent slip of the robot's other box bodies (torso, arms, thighs, shanks) on the field [m/s per N],
    with the same corner dampers as ``foot_slip_m_s_per_n`` (SimSpark: 5e-3 on every robot contact); None = their
    Coulomb friction (``body_friction``), the default: see "Body parts slip" in the docstring."""
    foot_slip_layer_m: float = 0.0
    """A foot corner holds (``foot_slip_m_s_per_n``) while it is lower than this above the field [m]; 0 = ODE's
    contact points, the corners below the field (1 mm measured worse, see "Feet slip as ODE's")."""
    noslip_iterations: int = 0
    """Iterations of MuJoCo's no-slip post-solve (0 = off): removes the slip the soft friction rows leave, as
    SimSpark's unbounded friction with its small force-dependent slip all but does."""

    @property
    def timestep_s(self) -> float:
        return self.cycle_s / self.substeps


#: The calibrated values (``motion-studio calibrate --write``), with their provenance; they override the
#: dataclass defaults above.
CALIBRATED_FILE = Path(__file__).with_name("physics_calibrated.toml")
#: Environment variable naming another physics file to use instead (a candidate calibration, for a trial).
PHYSICS_FILE_ENV = "NAO3D_PHYSICS_FILE"


def physics_file() -> Path | None:
    """The physics file in force: ``$NAO3D_PHYSICS_FILE`` if set, else `CALIBRATED_FILE` if present."""
    chosen = os.environ.get(PHYSICS_FILE_ENV)
    if chosen:
        path = Path(chosen)
        if not path.is_file():
            raise PhysicsFileError(f"{PHYSICS_FILE_ENV}={chosen}: no such physics file")
        return path
    return CALIBRATED_FILE if CALIBRATED_FILE.is_file() else None


def load_physics_file(path: Path) -> dict[str, object]:
    """The ``[physics]`` table of a calibration file as `PhysicsParams` field values (tuples for lists).

    Raises:
        ValueError: the file is not TOML or names an unknown field (the message names the file and key).
    """
    try:
        table = tomllib.loads(path.read_text(encoding="utf-8")).get("physics", {})
    except tomllib.TOMLDecodeError as error:
        raise PhysicsFileError(f"{path}: not TOML ({error})") from None
    known = {f.name for f in fields(PhysicsParams)}
    values: dict[str, object] = {}
    for key, value in table.items():
        if key not in known:
            raise PhysicsFileError(f"{path}: unknown physics parameter {key!r}; known: {', '.join(sorted(known))}")
        values[key] = tuple(value) if isinstance(value, list) else value
    return values


def default_physics_params(**overrides: object) -> PhysicsParams:
    """The default parameters (the calibrated file over the dataclass defaults), with named overrides
    (e.g. ``default_physics_params(substeps=4)``).

    Raises:
        TypeError: an override names no field (the message lists the fields).
    """
    base = PhysicsParams()
    chosen = physics_file()
    if chosen is not None:
        base = replace(base, **load_physics_file(chosen))  # type: ignore[arg-type]
    unknown = set(overrides) - set(PhysicsParams.__dataclass_fields__)
    if unknown:
        raise TypeError(f"unknown physics parameter(s) {sorted(unknown)}; known: "
                        f"{sorted(PhysicsParams.__dataclass_fields__)}")
    return replace(base, **overrides)  # type: ignore[arg-type]

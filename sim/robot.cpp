#include "sim/robot.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <btBulletDynamicsCommon.h>

#include "common/io/options_yaml.h"
#include "common/options_checker.h"
#include "sim/imu.h"

namespace corridorsim::sim {
namespace {

// Collision groups: wheels and caster touch only the floor; the chassis touches only the world's
// solids (it rests on its wheels and caster; testing it against the floor plane cost 30 % of a
// physics step). Solids never test against each other or the floor.
constexpr int kFloorGroup = 1 << 0;
constexpr int kSolidGroup = 1 << 1;
constexpr int kWheelGroup = 1 << 2;
constexpr int kChassisGroup = 1 << 3;

constexpr double kWheelMassKg = 0.5;  // each driven wheel with its hub
constexpr double kCasterMassKg = 0.2;
constexpr double kCasterRadiusM = 0.0375;    // Pioneer 3-DX rear caster: 75 mm diameter
constexpr double kCasterBehindAxleM = 0.20;  // caster contact behind the wheel axle
constexpr double kBodyBehindAxleM = 0.035;   // the body's centre lies this far behind the axle
constexpr double kBodyClearanceM = 0.05;     // floor to the underside of the body
constexpr double kFenderClearanceM = 0.02;   // floor to the underside of the wheels' footprint
constexpr double kContactSlopM = 1e-3;       // a chassis contact closer than this is reported

btVector3 Bt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }
Eigen::Vector3d Ei(const btVector3& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }

SE3 ToSE3(const btTransform& t) {
  const btQuaternion q = t.getRotation();
  return SE3(Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()), Ei(t.getOrigin()));
}
btTransform ToBt(const SE3& pose) {
  const Eigen::Quaterniond& q = pose.quaternion();
  return btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), Bt(pose.translation()));
}

}  // namespace

std::optional<OptionsProblem> RobotOptions::Check() const {
  if (auto problem = CheckOptionBounds(RobotOptionsTable(), *this)) return problem;
  OptionsChecker c;
  c.InRange(control_rate_hz, 1.0, physics_rate_hz, "control_rate_hz");
  c.Require(wheelbase_m + wheel_width_m <= body_width_m + 1e-9, "body_width_m",
            "must hold the wheels: at least wheelbase_m + wheel_width_m = " +
                FormatNumber(wheelbase_m + wheel_width_m) + " m");
  c.Require(wheel_diameter_m < body_height_m, "wheel_diameter_m",
            "must be less than body_height_m");
  c.Require(wheel_diameter_m < body_length_m, "wheel_diameter_m",
            "must be less than body_length_m");
  return c.problem();
}

std::vector<ChassisBox> ChassisBoxes(const RobotOptions& options) {
  const double body_bottom = kBodyClearanceM;
  const double body_height = options.body_height_m - body_bottom;
  const double body_width = options.wheelbase_m - options.wheel_width_m - 0.01;
  std::vector<ChassisBox> boxes;
  boxes.push_back({Eigen::Vector3d(-kBodyBehindAxleM, 0, body_bottom + body_height / 2),
                   Eigen::Vector3d(options.body_length_m / 2, body_width / 2, body_height / 2)});
  // The real wheels' footprint (their wheelbase carries E_b) out to the robot's full width.
  const double half_base =
      RealWheelGeometry(options.odometry, options.wheel_diameter_m, options.wheelbase_m)
          .wheelbase_m /
      2;
  const double fender_height = options.wheel_diameter_m - kFenderClearanceM;
  const double outer_half_width =
      std::max(options.body_width_m / 2, half_base + options.wheel_width_m / 2);
  const double fender_width = outer_half_width - (body_width / 2);
  for (int side : {-1, 1}) {
    boxes.push_back(
        {Eigen::Vector3d(0, side * (body_width / 2 + fender_width / 2),
                         kFenderClearanceM + fender_height / 2),
         Eigen::Vector3d(options.wheel_diameter_m / 2, fender_width / 2, fender_height / 2)});
  }
  return boxes;
}

Eigen::Vector2d WheelSpeedsFor(const RobotOptions& options, double linear_mps, double angular_rps) {
  const double radius = options.wheel_diameter_m / 2;
  const double half_base = options.wheelbase_m / 2;
  return {(linear_mps - angular_rps * half_base) / radius,
          (linear_mps + angular_rps * half_base) / radius};
}

struct RobotPhysics::Impl {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld dynamics{&dispatcher, &broadphase, &solver, &configuration};

  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btRigidBody>> static_bodies;
  std::vector<const worlds::CollisionBox*> boxes;  // per static body's user index
  std::unique_ptr<btCompoundShape> chassis_shape;
  std::unique_ptr<btRigidBody> chassis, left_wheel, right_wheel, caster;
  std::unique_ptr<btHingeConstraint> left_hinge, right_hinge;
  std::unique_ptr<btPoint2PointConstraint> caster_joint;
  SE3 body_from_robot;  // the chassis body frame is its centre of mass
  double max_wheel_speed_rps = 0.0;
  double max_impulse = 0.0;  // per step, N m s
  double step_s = 0.0;
  double left_hinge_angle = 0.0, right_hinge_angle = 0.0;  // last wrapped readings

  ~Impl() {
    // Constraints and bodies leave the world before they are destroyed.
    if (left_hinge) dynamics.removeConstraint(left_hinge.get());
    if (right_hinge) dynamics.removeConstraint(right_hinge.get());
    if (caster_joint) dynamics.removeConstraint(caster_joint.get());
    for (btRigidBody* body : {chassis.get(), left_wheel.get(), right_wheel.get(), caster.get()}) {
      if (body) dynamics.removeRigidBody(body);
    }
    for (auto& body : static_bodies) dynamics.removeRigidBody(body.get());
  }

  btRigidBody* AddStatic(std::unique_ptr<btCollisionShape> shape, const btTransform& pose,
                         int group, int mask, double friction, int user_index) {
    btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, shape.get());
    info.m_startWorldTransform = pose;
    info.m_friction = friction;
    auto body = std::make_unique<btRigidBody>(info);
    body->setUserIndex(user_index);
    dynamics.addRigidBody(body.get(), group, mask);
    shapes.push_back(std::move(shape));
    static_bodies.push_back(std::move(body));
    return static_bodies.back().get();
  }

  std::unique_ptr<btRigidBody> AddDynamic(btCollisionShape* shape, double mass,
                                          const btVector3& inertia, const btTransform& pose,
                                          double friction, int group, int mask) {
    btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, shape, inertia);
    info.m_startWorldTransform = pose;
    info.m_friction = friction;
    info.m_rollingFriction = 0.0;
    auto body = std::make_unique<btRigidBody>(info);
    body->setActivationState(DISABLE_DEACTIVATION);
    body->setUserIndex(-1);
    dynamics.addRigidBody(body.get(), group, mask);
    return body;
  }
};

RobotPhysics::RobotPhysics(const worlds::World& world, const RobotOptions& options,
                           const SE2& world_from_robot_start)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.dynamics.setGravity(btVector3(0, 0, -kGravityM_S2));  // sim/imu.h: the IMUs read it
  m.dynamics.getDispatchInfo().m_deterministicOverlappingPairs = true;
  // Ten solver iterations in a randomised (seeded, so deterministic) order: a fixed order
  // favours the constraints solved last and made the left and right wheels roll 5e-5 apart in
  // relative distance (odometry heading drifting 0.1 deg per 10 m straight); twenty iterations
  // halved that at 1.5 times the cost (bench_simulation, tests/sim/simulation_test.cpp).
  m.dynamics.getSolverInfo().m_numIterations = 10;
  m.dynamics.getSolverInfo().m_solverMode |= SOLVER_RANDMIZE_ORDER;
  m.dynamics.setForceUpdateAllAabbs(false);  // the solids never move: update only the robot's
  m.step_s = ToSeconds(options.physics_step_ns());
  m.max_wheel_speed_rps = options.max_wheel_speed_rps;
  m.max_impulse = options.max_wheel_torque_nm * m.step_s;

  // The floor (rooms share it) and the world's solids.
  m.AddStatic(std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0.0),
              btTransform::getIdentity(), kFloorGroup, kWheelGroup, 1.0, -1);
  m.boxes.reserve(world.collision_boxes.size());
  for (const worlds::CollisionBox& box : world.collision_boxes) {
    btTransform pose = btTransform::getIdentity();
    pose.setOrigin(Bt(box.center));
    m.AddStatic(std::make_unique<btBoxShape>(Bt(box.half_extents)), pose, kSolidGroup,
                kChassisGroup, 0.5, static_cast<int>(m.boxes.size()));
    m.boxes.push_back(&box);
  }

  // The real wheels carry the systematic odometry errors (Borenstein's E_d and E_b).
  const WheelGeometry real =
      RealWheelGeometry(options.odometry, options.wheel_diameter_m, options.wheelbase_m);
  const double r_left = real.left_diameter_m / 2, r_right = real.right_diameter_m / 2;
  const double half_base = real.wheelbase_m / 2;

  // Chassis masses and centre of mass, in the robot frame R.
  const double wheel_mass = kWheelMassKg;
  const double chassis_mass = options.mass_kg - 2 * wheel_mass - kCasterMassKg;
  const double body_height = options.body_height_m - kBodyClearanceM;
  // Chassis shape: the body box plus the wheels' footprint (so walls meet the real outline).
  const std::vector<ChassisBox> boxes = ChassisBoxes(options);
  const Eigen::Vector3d com_in_robot = boxes.front().center_in_robot;  // the body's centre
  m.body_from_robot = SE3(Eigen::Quaterniond::Identity(), -com_in_robot);
  m.chassis_shape = std::make_unique<btCompoundShape>();
  for (const ChassisBox& box : boxes) {
    auto shape = std::make_unique<btBoxShape>(Bt(box.half_extents));
    btTransform at = btTransform::getIdentity();
    at.setOrigin(Bt(box.center_in_robot - com_in_robot));
    m.chassis_shape->addChildShape(at, shape.get());
    m.shapes.push_back(std::move(shape));
  }
  btVector3 chassis_inertia;
  btBoxShape(btVector3(options.body_length_m / 2, options.body_width_m / 2, body_height / 2))
      .calculateLocalInertia(chassis_mass, chassis_inertia);

  const SE3 world_from_robot = SE3::FromSE2(world_from_robot_start);
  auto world_pose = [&](const Eigen::Vector3d& p_in_robot) {
    return ToBt(world_from_robot * SE3(Eigen::Quaterniond::Identity(), p_in_robot));
  };
  m.chassis = m.AddDynamic(m.chassis_shape.get(), chassis_mass, chassis_inertia,
                           world_pose(com_in_robot), 0.3, kChassisGroup, kSolidGroup);

  // Wheels: spheres of the wheel radius (see the header), on hinges about the robot's y axis.
  auto make_wheel = [&](double radius, double side) {
    auto shape = std::make_unique<btSphereShape>(radius);
    btVector3 inertia;
    shape->calculateLocalInertia(wheel_mass, inertia);
    auto body = m.AddDynamic(shape.get(), wheel_mass, inertia,
                             world_pose(Eigen::Vector3d(0, side * half_base, radius)),
                             options.wheel_friction, kWheelGroup, kFloorGroup);
    m.shapes.push_back(std::move(shape));
    return body;
  };
  m.left_wheel = make_wheel(r_left, 1.0);
  m.right_wheel = make_wheel(r_right, -1.0);
  auto make_hinge = [&](btRigidBody& wheel, double radius, double side) {
    const btVector3 pivot_in_chassis =
        Bt(Eigen::Vector3d(0, side * half_base, radius) - com_in_robot);
    auto hinge =
        std::make_unique<btHingeConstraint>(*m.chassis, wheel, pivot_in_chassis, btVector3(0, 0, 0),
                                            btVector3(0, 1, 0), btVector3(0, 1, 0));
    hinge->enableAngularMotor(true, 0.0, m.max_impulse);
    m.dynamics.addConstraint(hinge.get(), true);
    return hinge;
  };
  m.left_hinge = make_hinge(*m.left_wheel, r_left, 1.0);
  m.right_hinge = make_hinge(*m.right_wheel, r_right, -1.0);

  // Caster: a ball on a ball joint behind the axle.
  {
    auto shape = std::make_unique<btSphereShape>(kCasterRadiusM);
    btVector3 inertia;
    shape->calculateLocalInertia(kCasterMassKg, inertia);
    const Eigen::Vector3d caster_in_robot(-kCasterBehindAxleM, 0, kCasterRadiusM);
    m.caster = m.AddDynamic(shape.get(), kCasterMassKg, inertia, world_pose(caster_in_robot), 0.5,
                            kWheelGroup, kFloorGroup);
    m.shapes.push_back(std::move(shape));
    m.caster_joint = std::make_unique<btPoint2PointConstraint>(
        *m.chassis, *m.caster, Bt(caster_in_robot - com_in_robot), btVector3(0, 0, 0));
    m.dynamics.addConstraint(m.caster_joint.get(), true);
  }

  m.left_hinge_angle = m.left_hinge->getHingeAngle();
  m.right_hinge_angle = m.right_hinge->getHingeAngle();
  ReadState();
}

RobotPhysics::~RobotPhysics() = default;

void RobotPhysics::SetWheelSpeeds(double left_rps, double right_rps) {
  Impl& m = *impl_;
  const double limit = m.max_wheel_speed_rps;
  // The hinge's motor turns the wheel (body B) relative to the chassis about +y; a wheel turning
  // about the robot's +y rolls forward.
  m.left_hinge->enableAngularMotor(true, -std::clamp(left_rps, -limit, limit), m.max_impulse);
  m.right_hinge->enableAngularMotor(true, -std::clamp(right_rps, -limit, limit), m.max_impulse);
}

void RobotPhysics::Step() {
  impl_->dynamics.stepSimulation(impl_->step_s, 0, impl_->step_s);
  ++steps_;
  ReadState();
}

void RobotPhysics::ReadState() {
  Impl& m = *impl_;
  const SE3 world_from_body = ToSE3(m.chassis->getWorldTransform());
  state_.world_from_robot = world_from_body * m.body_from_robot;
  const Eigen::Vector3d omega = Ei(m.chassis->getAngularVelocity());
  const Eigen::Vector3d r = state_.world_from_robot.translation() - world_from_body.translation();
  state_.linear_velocity_in_world = Ei(m.chassis->getLinearVelocity()) + omega.cross(r);
  state_.angular_velocity_in_world = omega;

  // Cumulative wheel angles from the wrapped hinge angles (a step turns a wheel far less than pi).
  auto unwrap = [](btHingeConstraint& hinge, double& last, double& total) {
    const double now = hinge.getHingeAngle();
    total -= NormalizeAngle(now - last);
    last = now;
  };
  unwrap(*m.left_hinge, m.left_hinge_angle, state_.left_wheel_angle_rad);
  unwrap(*m.right_hinge, m.right_hinge_angle, state_.right_wheel_angle_rad);

  // The chassis' contacts with solids, the deepest per object, ordered by instance id.
  std::map<int, Contact> by_id;
  const int manifolds = m.dispatcher.getNumManifolds();
  for (int i = 0; i < manifolds; ++i) {
    const btPersistentManifold* manifold = m.dispatcher.getManifoldByIndexInternal(i);
    const btCollisionObject* a = manifold->getBody0();
    const btCollisionObject* b = manifold->getBody1();
    const btCollisionObject* other = a == m.chassis.get() ? b : b == m.chassis.get() ? a : nullptr;
    if (!other || other->getUserIndex() < 0) continue;
    const worlds::CollisionBox& box = *m.boxes[static_cast<std::size_t>(other->getUserIndex())];
    for (int k = 0; k < manifold->getNumContacts(); ++k) {
      const btManifoldPoint& point = manifold->getContactPoint(k);
      if (point.getDistance() > kContactSlopM) continue;
      Contact& c = by_id[box.instance_id];
      const double depth = -static_cast<double>(point.getDistance());
      if (c.instance_id == 0 || depth > c.depth_m) {
        c.instance_id = box.instance_id;
        c.semantic_class = box.semantic_class;
        c.position_in_world =
            Ei(other == b ? point.getPositionWorldOnB() : point.getPositionWorldOnA());
        c.depth_m = depth;
      }
    }
  }
  contacts_.clear();
  for (auto& [id, contact] : by_id) contacts_.push_back(contact);
}

}  // namespace corridorsim::sim

"""The worker's body: anthropometry, URDF and kinematics."""

"""agent.team: decisions shared by the team without a coordinator: who plays the ball, where the others stand."""

"""agent.world: the pieces of the world model (field geometry, frames, body kinematics, seen objects, state)."""

"""sim: the MuJoCo SimSpark world: physics, perceptors, effectors, referee, hosting, monitor output."""

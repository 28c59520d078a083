"""motions: the motion model, XML phase and Webots readers/writers, and the motion files the agent plays."""

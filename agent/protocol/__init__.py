"""agent.protocol: the project's one definition of the rcssserver3d wire language."""

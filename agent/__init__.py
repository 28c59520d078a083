"""agent: the soccer agent; runs without MuJoCo, against our server or the real rcssserver3d."""

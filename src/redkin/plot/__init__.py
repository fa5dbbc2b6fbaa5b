"""Matplotlib figures.  Plotting draws what the kinematics modules compute; it computes no kinematics of its own."""

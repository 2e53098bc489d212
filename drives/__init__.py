"""Drive trains (gear ratio, rotor inertia, efficiency, friction) and the sizing of motors and gearboxes."""

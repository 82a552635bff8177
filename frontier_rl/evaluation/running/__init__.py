"""Running a paired experiment: its configuration and jobs, the backends that run them (in this
process, a pool of worker processes or Ray) and the command's driver."""

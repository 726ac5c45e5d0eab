/* a program-side header (the option tables): the port must not reach it */
void hz_opt_probe(void);

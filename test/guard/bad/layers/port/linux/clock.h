/* a port header of the same name as nothing in programs: accepted */

// Ends what glsl_compat.h began: the GLSL spellings stay out of the rest of the file.
#undef precise
#undef GLSL_OUT
#undef GLSL_INOUT

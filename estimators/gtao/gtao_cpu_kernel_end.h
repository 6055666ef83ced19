// Ends what gtao_glsl_compat.h began: the GLSL spellings stay out of the rest of the file.
#undef precise
#undef GTAO_OUT
#undef GTAO_IMAGES_PARAM
#undef GTAO_IMAGES_ARG

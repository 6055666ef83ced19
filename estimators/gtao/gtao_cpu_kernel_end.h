// Ends what gtao_cpu_kernel.h began: the GLSL spellings stay out of the rest of the file.
#undef GTAO_IMAGES_PARAM
#undef GTAO_IMAGES_ARG
#include "estimators/screen_space/glsl_compat_end.h"

// Ends what hbao_cpu_kernel.h began: the GLSL spellings stay out of the rest of the file.
#undef HBAO_GROUP
#undef HBAO_RAY_GROUP
#undef HBAO_SCALAR_DEVICE
#undef HBAO_IMAGES_PARAM
#undef HBAO_IMAGES_ARG
#include "estimators/screen_space/glsl_compat_end.h"

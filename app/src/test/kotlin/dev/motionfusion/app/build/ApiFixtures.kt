package dev.motionfusion.app.build

import androidx.annotation.RequiresApi
import java.nio.file.Path
import java.nio.file.Paths

// Compiled with the tests, never with the app: ApiLevelGuardTest runs the API-26 check over these.

/** Path.of (Java 11) is not in the API-26 surface, and D8 does not backport it at min-api 26. */
internal object BadApiCall {
    fun path(): Path = Path.of("session")
}

/** The same call behind an SDK_INT check, marked as the build requires. */
internal object GuardedApiCall {
    @RequiresApi(33)
    fun path(): Path = Path.of("session")
}

/** What the API-26 code uses instead. */
internal object GoodApiCall {
    fun path(): Path = Paths.get("session")
}

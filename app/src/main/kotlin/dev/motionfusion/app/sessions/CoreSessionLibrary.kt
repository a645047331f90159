package dev.motionfusion.app.sessions

import java.io.File
import java.io.IOException

/** Reading sessions with the session format's reader of `fusion-core`. NOT BOUND YET (see CoreSessionFormat). */
internal object CoreSessionLibrary : SessionLibrary {
    override fun summary(dir: File): SessionSummary = throw IOException("the session format reader is not in this build yet")

    override fun angles(dir: File, maxPoints: Int): AngleSeries = throw IOException("the session format reader is not in this build yet")
}

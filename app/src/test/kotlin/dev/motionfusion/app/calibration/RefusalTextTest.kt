package dev.motionfusion.app.calibration

import dev.motionfusion.core.calib.Fit
import dev.motionfusion.core.calib.RefusalKind
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertNotEquals
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment

/**
 * A refused calibration says why in the screen's language: each kind of refusal fusion-core names
 * has its words in the resources, with fusion-core's figures in the language's number format; a
 * reason of no known kind is shown as fusion-core says it.
 */
@RunWith(RobolectricTestRunner::class)
class RefusalTextTest {
    private val app = RuntimeEnvironment.getApplication()
    private val core = "fusion-core's English words"

    private fun text(kind: RefusalKind) = CalibrationText.refusal(app, Fit.Refused(core, kind, listOf(1.0, 12.5, 65.0)))

    @Test
    fun `every kind of refusal in English and German, with the figures`() {
        for (language in listOf("en", "de")) {
            RuntimeEnvironment.setQualifiers(language)
            for (kind in RefusalKind.entries - RefusalKind.OTHER) {
                val t = text(kind)
                assertNotEquals("$language $kind", core, t)
                assertFalse("$language $kind: $t", Regex("""%(\d+\$)?[-,.\d]*[sdf]""").containsMatchIn(t))
            }
            assertEquals(core, text(RefusalKind.OTHER))
        }
        RuntimeEnvironment.setQualifiers("de")
        assertTrue(text(RefusalKind.NOT_STILL), text(RefusalKind.NOT_STILL).startsWith("1,0 s still (mindestens 13 s nötig)"))
        assertTrue(text(RefusalKind.AXIS_NEVER_DOWN), text(RefusalKind.AXIS_NEVER_DOWN).startsWith("die y-Achse zeigte nie nach unten"))
        RuntimeEnvironment.setQualifiers("en")
        assertTrue(text(RefusalKind.FEW_POSES), text(RefusalKind.FEW_POSES).startsWith("1 distinct still pose (at least 6 needed)"))
    }
}

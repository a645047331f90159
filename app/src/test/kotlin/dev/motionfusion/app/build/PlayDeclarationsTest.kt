package dev.motionfusion.app.build

import dev.motionfusion.app.build.BuildFiles.androidName
import dev.motionfusion.app.build.BuildFiles.child
import dev.motionfusion.app.build.BuildFiles.children
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.io.File

/**
 * What Play's review reads beside the APK stays what the app declares: the text of each `specialUse`
 * service's `PROPERTY_SPECIAL_USE_FGS_SUBTYPE` is quoted word for word in docs/RECORDING.md (the Play
 * Console's foreground-service declaration is written from it), and the privacy policy exists and is
 * linked from the README.
 */
class PlayDeclarationsTest {
    private val root = BuildFiles.repositoryRoot
    private val manifest = BuildFiles.parse(File(root, "app/src/main/AndroidManifest.xml"))

    @Test
    fun `every specialUse subtype text is quoted in the docs as the manifest has it`() {
        val docs = File(root, "docs/RECORDING.md").readText().replace(Regex("\\s+"), " ")
        val subtypes = manifest.child("application")!!.children("service")
            .filter { it.getAttributeNS(BuildFiles.ANDROID, "foregroundServiceType") == "specialUse" }
            .map { s -> s.children("property").single { it.androidName() == "android.app.PROPERTY_SPECIAL_USE_FGS_SUBTYPE" }.getAttributeNS(BuildFiles.ANDROID, "value") }
        assertEquals(1, subtypes.size, "the recording's service")
        for (text in subtypes) assertTrue("> $text" in docs, "docs/RECORDING.md does not quote the subtype text (as a '> ' quote):\n$text")
    }

    @Test
    fun `the privacy policy is there and linked from the README`() {
        val policy = File(root, "docs/PRIVACY.md")
        assertTrue(policy.isFile, "docs/PRIVACY.md")
        assertTrue("(docs/PRIVACY.md)" in File(root, "README.md").readText(), "README links docs/PRIVACY.md")
    }
}

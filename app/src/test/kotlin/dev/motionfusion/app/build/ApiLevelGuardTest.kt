package dev.motionfusion.app.build

import dev.motionfusion.app.build.BuildFiles.child
import dev.motionfusion.app.build.BuildFiles.children
import dev.motionfusion.app.build.BuildFiles.text
import org.codehaus.mojo.animal_sniffer.SignatureChecker
import org.codehaus.mojo.animal_sniffer.logging.Logger
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.io.File

/**
 * The API-level guard that `mvn verify` runs (animal-sniffer with the gummy-bears API-26
 * signature, configured in the root pom) does fail on a call missing at API 26: the same checker,
 * signature and annotation are run here over the classes of ApiFixtures.kt.
 */
class ApiLevelGuardTest {
    private val pom = BuildFiles.parse(File(BuildFiles.repositoryRoot, "pom.xml"))
    private val plugin = pom.child("build")!!.child("pluginManagement")!!.child("plugins")!!.children("plugin")
        .single { it.text("artifactId") == "animal-sniffer-maven-plugin" }
    private val annotations = plugin.child("configuration")!!.child("annotations")!!.children("annotation").map { it.textContent.trim() }

    private fun check(fixture: Class<*>): List<String> {
        val errors = ArrayList<String>()
        val log = object : Logger {
            override fun info(message: String) = Unit
            override fun info(message: String, t: Throwable) = Unit
            override fun debug(message: String) = Unit
            override fun debug(message: String, t: Throwable) = Unit
            override fun warn(message: String) = Unit
            override fun warn(message: String, t: Throwable) = Unit
            override fun error(message: String) { errors += message }
            override fun error(message: String, t: Throwable) { errors += message }
        }
        // As the plugin does: the project's own classes and its dependencies' are known; the signature covers the rest.
        val known = setOf(fixture.name, "kotlin.*", "androidx.*")
        val checker = BuildFiles.apiSignature.inputStream().use { SignatureChecker(it, known, log) }
        checker.setAnnotationTypes(annotations)
        checker.setSourcePath(emptyList())
        val classFile = File(fixture.protectionDomain.codeSource.location.toURI()).resolve(fixture.name.replace('.', '/') + ".class")
        assertTrue(classFile.isFile, "$classFile")
        checker.process(classFile)
        assertEquals(errors.isNotEmpty(), checker.isSignatureBroken)
        return errors
    }

    @Test
    fun `the build's check is the API-26 signature with the RequiresApi annotation`() {
        val signature = plugin.child("configuration")!!.child("signature")!!
        assertEquals("gummy-bears-api-26", signature.text("artifactId"))
        assertTrue("androidx.annotation.RequiresApi" in annotations, "$annotations")
        assertTrue(BuildFiles.apiSignature.name.startsWith("gummy-bears-api-26-"), "${BuildFiles.apiSignature}")
    }

    @Test
    fun `a call missing at API 26 fails the check`() {
        val errors = check(BadApiCall::class.java)
        assertEquals(1, errors.size, "$errors")
        assertTrue(errors.single().contains("java.nio.file.Path java.nio.file.Path.of(String, String[])"), errors.single())
    }

    @Test
    fun `the same call under RequiresApi and the API-26 replacement pass`() {
        assertEquals(emptyList<String>(), check(GuardedApiCall::class.java))
        assertEquals(emptyList<String>(), check(GoodApiCall::class.java))
    }
}

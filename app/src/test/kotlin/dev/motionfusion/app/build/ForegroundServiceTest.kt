package dev.motionfusion.app.build

import android.content.pm.ServiceInfo
import dev.motionfusion.app.build.BuildFiles.androidName
import dev.motionfusion.app.build.BuildFiles.child
import dev.motionfusion.app.build.BuildFiles.children
import dev.motionfusion.app.build.BuildFiles.componentClass
import dev.motionfusion.app.build.BuildFiles.manifestPackage
import dev.motionfusion.app.record.RecordingService
import dev.motionfusion.app.stream.StreamService
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.w3c.dom.Element

/**
 * Each foreground service's type (the recording's and the live stream's), the permission Android 14+
 * requires for that type, and the type the service passes to startForeground belong together: this
 * test fails when one of them changes without the others.
 *
 * It reads the manifest the test run is given (Maven's, with names as written, or the Android
 * Gradle Plugin's merged one, with names in full) and compares class names qualified. Under Maven it
 * also reads the manifest AGP's own merger makes of the same sources (ManifestMergerTest), so the
 * Gradle form is checked here too.
 */
class ForegroundServiceTest {
    private val manifest = BuildFiles.parse(BuildFiles.manifest)

    /** Manifest type name → the ServiceInfo constant and the permission it needs (Android 14 ServiceInfo docs). */
    private val types = mapOf(
        "health" to (ServiceInfo.FOREGROUND_SERVICE_TYPE_HEALTH to "android.permission.FOREGROUND_SERVICE_HEALTH"),
        "dataSync" to (ServiceInfo.FOREGROUND_SERVICE_TYPE_DATA_SYNC to "android.permission.FOREGROUND_SERVICE_DATA_SYNC"),
        "specialUse" to (ServiceInfo.FOREGROUND_SERVICE_TYPE_SPECIAL_USE to "android.permission.FOREGROUND_SERVICE_SPECIAL_USE"),
        "location" to (ServiceInfo.FOREGROUND_SERVICE_TYPE_LOCATION to "android.permission.FOREGROUND_SERVICE_LOCATION"),
        "connectedDevice" to (ServiceInfo.FOREGROUND_SERVICE_TYPE_CONNECTED_DEVICE to "android.permission.FOREGROUND_SERVICE_CONNECTED_DEVICE"),
    )

    /** Each foreground service of the app and the type it passes to startForeground. */
    private val services = mapOf(
        RecordingService::class.java.name to RecordingService.FOREGROUND_SERVICE_TYPE,
        StreamService::class.java.name to StreamService.FOREGROUND_SERVICE_TYPE,
    )

    /** The manifests read: the one given to this run and, under Maven, AGP's merger's. */
    private fun manifests(): List<Pair<String, Element>> = listOf("the test run's manifest" to manifest) +
        (if (AgpManifestMerger.available) listOf("AGP's merged manifest" to AgpManifestMerger.mergeApp(debuggable = true)) else emptyList())

    private fun Element.services() = child("application")!!.children("service")

    private fun Element.service(name: String) = services().single { it.componentClass() == name }

    private fun Element.permissions() = children("uses-permission").map { it.androidName() }.toSet()

    @Test
    fun `the manifest's type, its permission and the type passed to startForeground agree`() {
        for ((which, m) in manifests()) typesAgree(which, m)
    }

    @Test
    fun `the type's own requirements are met`() {
        for ((_, m) in manifests()) for (name in services.keys) requirementsMet(m.service(name), m.permissions())
    }

    private fun typesAgree(which: String, m: Element) {
        val permissions = m.permissions()
        for ((name, passed) in services) {
            val declared = m.service(name).getAttributeNS(BuildFiles.ANDROID, "foregroundServiceType")
            val (constant, permission) = types[declared] ?: error("$which: $name: foregroundServiceType '$declared' not known to this test")
            assertEquals(constant, passed, "$which: $name: type passed to startForeground")
            assertTrue(permission in permissions, "$which: $permission missing for type $declared")
        }
        assertTrue("android.permission.FOREGROUND_SERVICE" in permissions, which)
        // Every service of the app's own package is one of these (a new one is checked too); libraries' are not the app's.
        val declaredServices = m.services().map { it.componentClass() }.filter { it.startsWith(m.manifestPackage() + ".") }
        assertEquals(services.keys, declaredServices.toSet(), which)
    }

    private fun requirementsMet(service: Element, permissions: Set<String>) {
        when (val declared = service.getAttributeNS(BuildFiles.ANDROID, "foregroundServiceType")) {
            // Play reviews a specialUse service by the subtype the manifest gives it.
            "specialUse" -> {
                val subtype = service.children("property").singleOrNull { it.androidName() == "android.app.PROPERTY_SPECIAL_USE_FGS_SUBTYPE" }
                assertTrue(subtype != null, "a specialUse service needs its PROPERTY_SPECIAL_USE_FGS_SUBTYPE property")
                assertTrue(subtype!!.getAttributeNS(BuildFiles.ANDROID, "value").length >= 40, "the subtype says what the service does")
            }
            // FOREGROUND_SERVICE_HEALTH also needs ACTIVITY_RECOGNITION, BODY_SENSORS or HIGH_SAMPLING_RATE_SENSORS.
            "health" -> {
                val anyOf = setOf("android.permission.ACTIVITY_RECOGNITION", "android.permission.BODY_SENSORS", "android.permission.HIGH_SAMPLING_RATE_SENSORS")
                assertTrue(permissions.any { it in anyOf }, "$permissions")
            }
            // Android 14+ starts a connectedDevice service only for an app that holds one of these (ServiceInfo docs).
            "connectedDevice" -> {
                val anyOf = setOf(
                    "android.permission.BLUETOOTH_ADVERTISE", "android.permission.BLUETOOTH_CONNECT", "android.permission.BLUETOOTH_SCAN",
                    "android.permission.CHANGE_NETWORK_STATE", "android.permission.CHANGE_WIFI_STATE", "android.permission.CHANGE_WIFI_MULTICAST_STATE",
                    "android.permission.NFC", "android.permission.TRANSMIT_IR", "android.permission.UWB_RANGING",
                )
                assertTrue(permissions.any { it in anyOf }, "$permissions")
            }
            else -> error("no requirements known for type $declared")
        }
    }
}
